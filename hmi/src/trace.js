// The HMI's trace records (docs/tracing.md). Opened with ?trace=1, the page reports the receipt
// of every LCRW message on <prefix>/<station>/hmi/trace; the native launcher writes them to the
// run's trace folder, and scripts/report measures the last hop (broker → driver's page) and
// state change → warning at the HMI. The time stamps are this browser's wall clock: on another
// computer than the stations, its clock must be synchronised (NTP) for the figures to hold.

// 2004-01-01T00:00:00Z in Unix ms: TimestampIts' epoch (ETSI TS 102 894-2), as the station's.
const ITS_EPOCH_UNIX_MS = 1072915200000;

// GenerationDeltaTime (TimestampIts mod 65536) of the CAM whose state time is unixMs: what the
// station's its.mqtt record names the neighbour's CAM by.
export function generationDeltaTime(unixMs) {
  return (((unixMs - ITS_EPOCH_UNIX_MS) % 65536) + 65536) % 65536;
}

// Wall-clock ms (fractional, from performance.timeOrigin + performance.now()) → ns since the
// Unix epoch as a decimal string: a JS number cannot hold ~1.8e18 exactly, JSON integers can.
export function nsString(ms) {
  let whole = Math.floor(ms);
  let frac = Math.round((ms - whole) * 1e6);
  if (frac >= 1e6) {
    whole += 1;
    frac -= 1e6;
  }
  return `${whole}${String(frac).padStart(6, '0')}`;
}

export function traceTopic(prefix, station) {
  return `${prefix}/${station}/hmi/trace`;
}

// The hmi.signal record of a signal message (its/<station>/app/signal, issue 34) received at
// receivedMs and drawn at shownMs, with its key (station/intersection/group/state, '' when the
// car left the lane): the page writes one only when the key changes, the end of "light change
// in the sim → state at the driver's HMI"; the message comes 10 times a second. null for any
// other message or one without the fields that name the group.
export function signalReceipt(prefix, topic, payload, receivedMs, shownMs) {
  const parts = topic.split('/');
  if (parts.length !== 4 || parts[0] !== prefix || parts[2] !== 'app' || parts[3] !== 'signal' || !/^\d+$/.test(parts[1])) {
    return null;
  }
  let m;
  try {
    m = JSON.parse(payload)?.message;
  } catch {
    return null;
  }
  if (!m || typeof m !== 'object') {
    return null;
  }
  const station = Number(parts[1]);
  const left = m.lane === null || m.lane_id === null;
  const ok = (v) => Number.isInteger(v) && v >= 0;
  if (!left && (!ok(m.intersection_id) || !ok(m.signal_group) || typeof m.state !== 'string')) {
    return null;
  }
  const named = left ? { station, light: '' } : { station, intersection_id: m.intersection_id, signal_group: m.signal_group, light: m.state };
  const fields = JSON.stringify({ proc: 'hmi', ev: 'hmi.signal', ...named });
  return {
    key: left ? '' : `${station}/${m.intersection_id}/${m.signal_group}/${m.state}`,
    record: `{"ts":${nsString(receivedMs)},${fields.slice(1, -1)},"shown_ns":${nsString(shownMs)}}`,
  };
}

// The hmi.lcrw record of an LCRW message (topic, payload text) received at receivedMs and put
// on the page at shownMs; null for any other message or one without the fields that name it.
export function lcrwReceipt(prefix, topic, payload, receivedMs, shownMs) {
  const parts = topic.split('/');
  if (parts.length !== 4 || parts[0] !== prefix || parts[2] !== 'app' || parts[3] !== 'lcrw') {
    return null;
  }
  let w;
  try {
    w = JSON.parse(payload)?.message;
  } catch {
    return null;
  }
  const ok = (v) => Number.isInteger(v) && v >= 0;
  if (!w || !ok(w.station_id) || !ok(w.other_station_id) || !ok(w.other_state_time) ||
      !ok(w.own_state_time) || typeof w.event !== 'string') {
    return null;
  }
  const fields = JSON.stringify({
    proc: 'hmi',
    ev: 'hmi.lcrw',
    station: w.station_id,
    from: w.other_station_id,
    gdt: generationDeltaTime(w.other_state_time),
    own_ms: w.own_state_time,
    event: w.event,
  });
  return `{"ts":${nsString(receivedMs)},${fields.slice(1, -1)},"shown_ns":${nsString(shownMs)}}`;
}

// The hmi.denm record of a DENM message (its/<station>/in/denm/<origin>, or the station's own on
// its/<station>/out/denm) received at receivedMs and put in the road-event list at shownMs: the
// topic's station, the event's action ID (origin, seq), the direction and whether it ends the
// event. scripts/report joins it to the station's its.denm_rx of the same action ID. null for
// any other message or one without an action ID.
export function denmReceipt(prefix, topic, payload, receivedMs, shownMs) {
  const parts = topic.split('/');
  const incoming = parts.length === 5 && parts[2] === 'in';
  const outgoing = parts.length === 4 && parts[2] === 'out';
  if (parts[0] !== prefix || parts[3] !== 'denm' || !(incoming || outgoing) || !/^\d+$/.test(parts[1])) {
    return null;
  }
  let mc;
  try {
    mc = JSON.parse(payload)?.message?.management_container;
  } catch {
    return null;
  }
  const id = mc?.action_id;
  const ok = (v) => Number.isInteger(v) && v >= 0;
  if (!id || !ok(id.originating_station_id) || !ok(id.sequence_number)) {
    return null;
  }
  const fields = JSON.stringify({
    proc: 'hmi',
    ev: 'hmi.denm',
    station: Number(parts[1]),
    origin: id.originating_station_id,
    seq: id.sequence_number,
    dir: parts[2],
    term: mc.termination !== undefined,
  });
  return `{"ts":${nsString(receivedMs)},${fields.slice(1, -1)},"shown_ns":${nsString(shownMs)}}`;
}
