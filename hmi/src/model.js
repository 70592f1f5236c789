// The HMI's state, fed by MQTT messages; pure (no DOM), so node can test it.
import * as etsi from './etsi.js';

export const NEIGHBOUR_TIMEOUT_MS = 3000;
// LCRW updates an active warning at every evaluation; one not refreshed for this long is gone
// (its clear message may have been lost with a connection).
export const WARNING_TIMEOUT_MS = 2000;

export function createModel(prefix = 'its') {
  return {
    prefix,
    station: null,
    stations: new Map(), // id → { online, dropped, lastSeen }
    own: null,
    neighbours: new Map(), // id → { lat, lon, heading, speed, length, width, receivedAt }
    warnings: new Map(), // other station id → warning message (+ receivedAt)
    denms: [], // newest first
  };
}

export function selectStation(model, id) {
  model.station = id === null ? null : String(id);
  model.own = null;
  model.neighbours.clear();
  model.warnings.clear();
  model.denms = [];
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

// Applies one message; returns what changed: 'stations' | 'own' | 'neighbours' | 'warning' |
// 'denm' | null (ignored).
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
  if (parts[2] === 'app' && parts[3] === 'lcrw') {
    const w = body.message ?? {};
    const other = String(w.other_station_id);
    if (w.event === 'cleared') {
      model.warnings.delete(other);
    } else {
      model.warnings.set(other, { ...w, receivedAt: now });
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
    if (now - w.receivedAt > WARNING_TIMEOUT_MS) {
      model.warnings.delete(id);
      changed = true;
    }
  }
  return changed;
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
