// The HMI's state, fed by MQTT messages; pure (no DOM), so node can test it.
import * as etsi from './etsi.js';

export const NEIGHBOUR_TIMEOUT_MS = 3000;
// LCRW updates an active warning at every evaluation; one not refreshed for this long is gone
// (its clear message may have been lost with a connection).
export const WARNING_TIMEOUT_MS = 2000;
// A warning stays up at least this long after it was raised, even when its clear comes
// sooner: LCRW can raise and clear within 30 ms as a gap closes and opens, too short for a
// driver to see (as the sim-client's HUD, MonitorConfig::warning_min_display).
export const WARNING_MIN_DISPLAY_MS = 1000;
// The own lane's signal (issue 34) comes at up to 10 Hz while the car is on an ingress lane:
// one older than this is gone (as the sim-client's HUD, MonitorConfig::signal_timeout).
export const SIGNAL_TIMEOUT_MS = 1000;
// A red-light warning neither updated nor cleared for this long is gone, as LCRW's, unless
// the fresh signal message still says rlvw.
export const RLVW_TIMEOUT_MS = 2000;

// The MQTT contract's signal states (DSRC MovementPhaseState folded for the driver).
export const SIGNAL_STATES = ['red', 'red_amber', 'amber', 'green', 'dark', 'unavailable'];
// ISO TS 19091 DSRC MovementPhaseState names, 0..9.
export const MOVEMENT_PHASE_STATES = [
  'unavailable', 'dark', 'stop-Then-Proceed', 'stop-And-Remain', 'pre-Movement',
  'permissive-Movement-Allowed', 'protected-Movement-Allowed', 'permissive-clearance',
  'protected-clearance', 'caution-Conflicting-Traffic',
];

export function createModel(prefix = 'its') {
  return {
    prefix,
    station: null,
    stations: new Map(), // id → { online, dropped, lastSeen }
    own: null,
    neighbours: new Map(), // id → { lat, lon, heading, speed, length, width, receivedAt }
    warnings: new Map(), // other station id → warning message (+ receivedAt)
    denms: [], // newest first
    signal: null, // the own lane's signal message (+ receivedAt), while on an ingress lane
    rlvw: null, // the active red-light warning (+ receivedAt)
    rejected: 0, // signal and RLVW messages not as the contract says
    lastError: '',
  };
}

export function selectStation(model, id) {
  model.station = id === null ? null : String(id);
  model.own = null;
  model.neighbours.clear();
  model.warnings.clear();
  model.denms = [];
  model.signal = null;
  model.rlvw = null;
}

export function subscriptions(model) {
  const subs = [`${model.prefix}/+/status`, `${model.prefix}/+/state`];
  if (model.station !== null) {
    subs.push(`${model.prefix}/${model.station}/#`);
  }
  return subs;
}

function kinematics(msg) {
  const pos = msg.basic_container?.reference_position ?? {};
  const hf = msg.high_frequency_container ?? {};
  return {
    lat: etsi.latitudeDeg(pos.latitude),
    lon: etsi.longitudeDeg(pos.longitude),
    heading: etsi.headingDeg(hf.heading),
    speed: etsi.speedMps(hf.speed),
    reversing: hf.drive_direction === 1,
    length: etsi.lengthM(hf.vehicle_length),
    width: etsi.widthM(hf.vehicle_width),
  };
}

const isInt = (v, lo, hi) => Number.isInteger(v) && v >= lo && v <= hi;
const isNum = (v) => typeof v === 'number' && Number.isFinite(v);
const isNumOrNull = (v) => v === null || isNum(v);

// Why a signal message's `message` is not as issue 34's contract says; '' when it is.
// DSRC ranges: IntersectionID 0..65535, SignalGroupID and LaneID 0..255.
export function signalError(m) {
  if (!isInt(m.intersection_id, 0, 65535)) return 'intersection_id';
  if (!isInt(m.signal_group, 0, 255)) return 'signal_group';
  if (!isInt(m.lane_id, 0, 255)) return 'lane_id';
  if (!SIGNAL_STATES.includes(m.state)) return 'state';
  if (!MOVEMENT_PHASE_STATES.includes(m.event_state)) return 'event_state';
  if (!isNumOrNull(m.time_to_change_s) || Math.abs(m.time_to_change_s) > 3600) return 'time_to_change_s';
  if (m.likely_time_to_change_s !== undefined && (!isNumOrNull(m.likely_time_to_change_s) || Math.abs(m.likely_time_to_change_s) > 3600)) {
    return 'likely_time_to_change_s';
  }
  if (!isNum(m.distance_to_stop_line_m) || Math.abs(m.distance_to_stop_line_m) > 100000) return 'distance_to_stop_line_m';
  const a = m.advice;
  if (a !== undefined && a !== null && !(typeof a === 'object' && isNum(a.min_speed_kmh) && isNum(a.max_speed_kmh)
      && a.min_speed_kmh >= 0 && a.min_speed_kmh <= a.max_speed_kmh && a.max_speed_kmh <= 500)) {
    return 'advice';
  }
  if (m.rlvw !== undefined && typeof m.rlvw !== 'boolean') return 'rlvw';
  return '';
}

export function rlvwError(m) {
  if (!['raised', 'updated', 'cleared'].includes(m.event)) return 'event';
  if (!isInt(m.intersection_id, 0, 65535)) return 'intersection_id';
  if (!isInt(m.signal_group, 0, 255)) return 'signal_group';
  if (m.event === 'cleared') return '';
  if (!isInt(m.lane_id, 0, 255)) return 'lane_id';
  if (!isNum(m.distance_to_stop_line_m)) return 'distance_to_stop_line_m';
  if (!isNum(m.speed_mps) || m.speed_mps < 0) return 'speed_mps';
  if (!isNumOrNull(m.time_to_red_s)) return 'time_to_red_s';
  if (!isNum(m.stopping_distance_m) || m.stopping_distance_m < 0) return 'stopping_distance_m';
  return '';
}

function reject(model, topic, why) {
  model.rejected += 1;
  model.lastError = `${topic}: ${why}`;
  return null;
}

// Applies one message; returns what changed: 'stations' | 'own' | 'neighbours' | 'warning' |
// 'denm' | 'signal' | 'rlvw' | null (ignored).
export function handleMessage(model, topic, text, now = Date.now()) {
  const parts = topic.split('/');
  if (parts.length < 3 || parts[0] !== model.prefix) {
    return null;
  }
  const id = parts[1];
  let body;
  try {
    body = JSON.parse(text);
  } catch {
    return null; // not ours to show; a bad publisher must not break the HMI
  }
  if (body === null || typeof body !== 'object') {
    return null;
  }
  const entry = model.stations.get(id) ?? { online: null, dropped: 0, lastSeen: 0 };
  model.stations.set(id, entry);

  if (parts[2] === 'status') {
    entry.online = body.online === true;
    entry.dropped = Number(body.dropped ?? 0);
    return 'stations';
  }
  if (parts[2] === 'state') {
    entry.lastSeen = now;
    if (id !== model.station) {
      return 'stations';
    }
    const msg = body.message ?? {};
    model.own = { ...kinematics(msg), fix: msg.gnss?.fix ?? 'none', satellites: msg.gnss?.satellites_used, receivedAt: now };
    return 'own';
  }
  if (id !== model.station) {
    return null;
  }
  if (parts[2] === 'in' && parts[3] === 'cam' && parts.length === 5) {
    const msg = body.message ?? {};
    model.neighbours.set(parts[4], { ...kinematics(msg), receivedAt: now });
    return 'neighbours';
  }
  if ((parts[2] === 'in' || parts[2] === 'out') && parts[3] === 'denm') {
    const msg = body.message ?? {};
    const mc = msg.management_container ?? {};
    const ev = msg.situation_container?.event_type ?? {};
    const key = `${mc.action_id?.originating_station_id}/${mc.action_id?.sequence_number}`;
    const denm = {
      key,
      direction: parts[2],
      originator: mc.action_id?.originating_station_id,
      seq: mc.action_id?.sequence_number,
      text: etsi.causeText(ev.cause, ev.subcause),
      cause: ev.cause,
      subcause: ev.subcause,
      lat: etsi.latitudeDeg(mc.event_position?.latitude),
      lon: etsi.longitudeDeg(mc.event_position?.longitude),
      terminated: mc.termination !== undefined,
      receivedAt: now,
    };
    model.denms = [denm, ...model.denms.filter((d) => d.key !== key)].slice(0, 20);
    return 'denm';
  }
  if (parts[2] === 'app' && parts[3] === 'signal') {
    const m = body.message;
    if (m === null || typeof m !== 'object') {
      return reject(model, topic, 'no message object');
    }
    // Leaving the ingress lane: one message with "lane": null (a null lane_id reads the same).
    if (m.lane === null || m.lane_id === null) {
      model.signal = null;
      return 'signal';
    }
    const bad = signalError(m);
    if (bad) {
      return reject(model, topic, `message.${bad} missing or out of range`);
    }
    model.signal = { ...m, receivedAt: now };
    return 'signal';
  }
  if (parts[2] === 'app' && parts[3] === 'rlvw') {
    const m = body.message;
    if (m === null || typeof m !== 'object') {
      return reject(model, topic, 'no message object');
    }
    const bad = rlvwError(m);
    if (bad) {
      return reject(model, topic, `message.${bad} missing or out of range`);
    }
    if (m.event === 'cleared') {
      // Only the warning it names: a late clear of a former lane leaves a newer one up.
      if (model.rlvw && model.rlvw.intersection_id === m.intersection_id && model.rlvw.signal_group === m.signal_group) {
        model.rlvw = null;
      }
    } else {
      model.rlvw = { ...m, receivedAt: now };
    }
    return 'rlvw';
  }
  if (parts[2] === 'app' && parts[3] === 'lcrw') {
    const w = body.message ?? {};
    const other = String(w.other_station_id);
    const up = model.warnings.get(other);
    if (w.event === 'cleared') {
      if (up && now - up.shownSince < WARNING_MIN_DISPLAY_MS) {
        up.cleared = true; // expire() takes it down when its minimum display ends
      } else {
        model.warnings.delete(other);
      }
    } else {
      // Raised again while still up (even after an early clear): the same episode.
      const shownSince = up ? up.shownSince : now;
      model.warnings.set(other, { ...w, receivedAt: now, shownSince });
    }
    return 'warning';
  }
  return null;
}

// Forgets silent neighbours and stale warnings; returns true if anything went.
export function expire(model, now = Date.now()) {
  let changed = false;
  for (const [id, n] of model.neighbours) {
    if (now - n.receivedAt > NEIGHBOUR_TIMEOUT_MS) {
      model.neighbours.delete(id);
      changed = true;
    }
  }
  for (const [id, w] of model.warnings) {
    const over = w.cleared ? now - w.shownSince >= WARNING_MIN_DISPLAY_MS : now - w.receivedAt > WARNING_TIMEOUT_MS;
    if (over) {
      model.warnings.delete(id);
      changed = true;
    }
  }
  if (model.signal && now - model.signal.receivedAt > SIGNAL_TIMEOUT_MS) {
    model.signal = null;
    changed = true;
  }
  if (model.rlvw && now - model.rlvw.receivedAt > RLVW_TIMEOUT_MS && !model.signal?.rlvw) {
    model.rlvw = null;
    changed = true;
  }
  return changed;
}

// What the signal panel shows (as the sim-client's HUD, sim-client/v2x/signal_panel.hpp), or
// null without a fresh signal: the lamps lit by state (none for dark and unavailable, drawn
// grey), the time to change in whole seconds rounded up as junction countdowns count (the
// likely time if known, else the minimum; both aged since the message came), the distance to
// the stop line, and the GLOSA advice in whole km/h inside the advised range.
export function signalPanel(model, now = Date.now()) {
  const s = model.signal;
  if (!s || now - s.receivedAt > SIGNAL_TIMEOUT_MS) {
    return null;
  }
  const age = (now - s.receivedAt) / 1000;
  const t = isNum(s.likely_time_to_change_s) ? s.likely_time_to_change_s : s.time_to_change_s;
  let countdown = '';
  if (isNum(t)) {
    countdown = `${Math.ceil(Math.max(0, t - age))} s`;
  }
  let advice = '';
  if (s.advice) {
    const lo = Math.ceil(s.advice.min_speed_kmh);
    const hi = Math.floor(s.advice.max_speed_kmh);
    advice = lo < hi ? `${lo}–${hi} km/h` : `${Math.round((s.advice.min_speed_kmh + s.advice.max_speed_kmh) / 2)} km/h`;
  }
  return {
    state: s.state,
    red: s.state === 'red' || s.state === 'red_amber',
    amber: s.state === 'amber' || s.state === 'red_amber',
    green: s.state === 'green',
    countdown,
    countdownIsLikely: isNum(s.likely_time_to_change_s),
    distance: `${Math.max(0, s.distance_to_stop_line_m).toFixed(0)} m`,
    advice,
    caption: `group ${s.signal_group} · lane ${s.lane_id}`,
  };
}

// The red-light banner's line, or null when no RLVW is active.
export function rlvwBanner(model, now = Date.now()) {
  const r = model.rlvw;
  if (!r) {
    return null;
  }
  const fresh = now - r.receivedAt <= RLVW_TIMEOUT_MS || (model.signal?.rlvw === true && now - model.signal.receivedAt <= SIGNAL_TIMEOUT_MS);
  if (!fresh) {
    return null;
  }
  const ttr = isNum(r.time_to_red_s) ? r.time_to_red_s - (now - r.receivedAt) / 1000 : null;
  return {
    when: ttr !== null && ttr > 0 ? `red in ${ttr.toFixed(1)} s` : 'red',
    distance: `${Math.max(0, r.distance_to_stop_line_m).toFixed(0)} m`,
    speed: `${(r.speed_mps * 3.6).toFixed(0)} km/h`,
  };
}

// The warning the banner shows: the most urgent one.
export function topWarning(model) {
  let best = null;
  for (const w of model.warnings.values()) {
    const ttc = w.ttc_s ?? Infinity;
    if (best === null || ttc < (best.ttc_s ?? Infinity)) {
      best = w;
    }
  }
  return best;
}

export function formatTtc(ttc) {
  return ttc === null || ttc === undefined || !Number.isFinite(ttc) ? '–' : `${ttc.toFixed(1)} s`;
}
