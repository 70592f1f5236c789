// Unit tests of the HMI's model (pure JS, no browser): `node --test hmi/tests/model_test.mjs`.
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { causeText, offsetM } from '../src/etsi.js';
import {
  createModel,
  expire,
  formatTtc,
  handleMessage,
  rlvwBanner,
  selectStation,
  signalPanel,
  subscriptions,
  topWarning,
  RLVW_TIMEOUT_MS,
  SIGNAL_TIMEOUT_MS,
  WARNING_MIN_DISPLAY_MS,
  WARNING_TIMEOUT_MS,
} from '../src/model.js';

const env = (type, message) => JSON.stringify({ type, origin: 'self', version: '1.0.0', source_uuid: 'station-1', timestamp: 0, message });

function lcrw(other, event, ttc, severity = 'warning') {
  return env('lcrw_warning', { station_id: 1, other_station_id: other, event, ttc_s: ttc, severity, collision_case: 'frontal' });
}

test('subscribes to station list and the chosen station', () => {
  const m = createModel('its');
  assert.deepEqual(subscriptions(m), ['its/+/status', 'its/+/state']);
  selectStation(m, 1001);
  assert.deepEqual(subscriptions(m), ['its/+/status', 'its/+/state', 'its/1001/#']);
});

test('state in CDD units becomes SI', () => {
  const m = createModel();
  selectStation(m, '1');
  const what = handleMessage(m, 'its/1/state', env('state', {
    basic_container: { reference_position: { latitude: 480000000, longitude: 110000000 } },
    high_frequency_container: { heading: 900, speed: 1389, drive_direction: 0 },
    gnss: { fix: '3d', satellites_used: 9 },
  }), 1000);
  assert.equal(what, 'own');
  assert.equal(m.own.lat, 48);
  assert.equal(m.own.heading, 90);
  assert.equal(m.own.speed, 13.89);
  assert.equal(m.own.fix, '3d');
});

test('other stations only update the station list', () => {
  const m = createModel();
  selectStation(m, '1');
  assert.equal(handleMessage(m, 'its/2/state', env('state', {})), 'stations');
  assert.equal(m.own, null);
  assert.equal(handleMessage(m, 'its/2/app/lcrw', lcrw(1, 'raised', 2)), null);
  assert.equal(m.warnings.size, 0);
  assert.ok(m.stations.has('2'));
});

test('status carries online flag and dropped count', () => {
  const m = createModel();
  handleMessage(m, 'its/7/status', JSON.stringify({ online: true, dropped: 3 }));
  assert.deepEqual({ online: m.stations.get('7').online, dropped: m.stations.get('7').dropped }, { online: true, dropped: 3 });
});

test('warnings: raised, most urgent first, cleared, expired', () => {
  const m = createModel();
  selectStation(m, '1');
  handleMessage(m, 'its/1/app/lcrw', lcrw(2, 'raised', 2.8), 0);
  handleMessage(m, 'its/1/app/lcrw', lcrw(3, 'raised', 1.2, 'critical'), 0);
  assert.equal(topWarning(m).other_station_id, 3);
  handleMessage(m, 'its/1/app/lcrw', lcrw(3, 'cleared', null), WARNING_MIN_DISPLAY_MS + 100);
  assert.equal(topWarning(m).other_station_id, 2);
  assert.equal(expire(m, WARNING_TIMEOUT_MS - 1), false);
  assert.equal(expire(m, WARNING_TIMEOUT_MS + 1), true);
  assert.equal(topWarning(m), null);
});

test('warnings: an early clear keeps the warning up for its minimum display', () => {
  const m = createModel();
  selectStation(m, '1');
  handleMessage(m, 'its/1/app/lcrw', lcrw(2, 'raised', 1.6), 0);
  handleMessage(m, 'its/1/app/lcrw', lcrw(2, 'cleared', null), 30);
  assert.equal(expire(m, 30), false);
  assert.equal(topWarning(m).other_station_id, 2);
  assert.equal(expire(m, WARNING_MIN_DISPLAY_MS - 1), false);
  assert.equal(expire(m, WARNING_MIN_DISPLAY_MS), true);
  assert.equal(topWarning(m), null);
  // Raised again while held: the same episode; the next clear, past the minimum, is at once.
  handleMessage(m, 'its/1/app/lcrw', lcrw(2, 'raised', 2.0), 5000);
  handleMessage(m, 'its/1/app/lcrw', lcrw(2, 'cleared', null), 5200);
  handleMessage(m, 'its/1/app/lcrw', lcrw(2, 'raised', 1.4), 5500);
  assert.equal(expire(m, 6050), false);
  assert.equal(topWarning(m).ttc_s, 1.4);
  handleMessage(m, 'its/1/app/lcrw', lcrw(2, 'cleared', null), 6100);
  assert.equal(topWarning(m), null);
});

test('DENMs listed newest first, updates replace, termination shown', () => {
  const m = createModel();
  selectStation(m, '1');
  const denm = (seq, termination) => env('denm', {
    management_container: { action_id: { originating_station_id: 2, sequence_number: seq }, ...(termination === undefined ? {} : { termination }) },
    situation_container: { event_type: { cause: 97, subcause: 1 } },
  });
  handleMessage(m, 'its/1/in/denm/2', denm(1));
  handleMessage(m, 'its/1/in/denm/2', denm(2));
  handleMessage(m, 'its/1/in/denm/2', denm(1, 0));
  assert.equal(m.denms.length, 2);
  assert.equal(m.denms[0].key, '2/1');
  assert.equal(m.denms[0].terminated, true);
  assert.equal(m.denms[0].text, 'Collision risk (longitudinal)');
  // The action ID travels with each listed event (the page's li data-originator/data-seq).
  assert.deepEqual(m.denms.map((d) => [d.originator, d.seq, d.direction]), [[2, 1, 'in'], [2, 2, 'in']]);
});

test('garbage is ignored', () => {
  const m = createModel();
  selectStation(m, '1');
  assert.equal(handleMessage(m, 'its/1/state', 'not json'), null);
  assert.equal(handleMessage(m, 'its/1/state', 'null'), null);
  assert.equal(handleMessage(m, 'other/1/state', '{}'), null);
  assert.equal(handleMessage(m, 'its', '{}'), null);
});

test('formatting and geometry helpers', () => {
  assert.equal(formatTtc(2.44), '2.4 s');
  assert.equal(formatTtc(null), '–');
  assert.equal(causeText(94, 0), 'Stationary vehicle');
  const d = offsetM(48, 11, 48.001, 11);
  assert.ok(Math.abs(d.north - 111.2) < 0.5);
  assert.ok(Math.abs(d.east) < 1e-9);
});

// Issue 34: the own lane's signal and the red-light warning (the MQTT contract's payloads).
function signal(over = {}) {
  return env('signal', {
    intersection_id: 1, signal_group: 3, lane_id: 2, state: 'red', event_state: 'stop-And-Remain',
    time_to_change_s: 6.2, likely_time_to_change_s: 7.4, distance_to_stop_line_m: 41.6,
    advice: null, rlvw: false, ...over,
  });
}

function rlvw(event, over = {}) {
  return env('rlvw_warning', {
    station_id: 1, intersection_id: 1, signal_group: 3, lane_id: 2, event, severity: 'warning',
    distance_to_stop_line_m: 40.2, speed_mps: 16.7, time_to_red_s: 1.0, stopping_distance_m: 63.1,
    clear_reason: event === 'cleared' ? 'passed' : 'none', raised_at: 0, updated_at: 0, ...over,
  });
}

test('signal panel: lamps lit by state, grey (none lit) when dark or unavailable', () => {
  const cases = [
    ['red', 'stop-And-Remain', [true, false, false]],
    ['red_amber', 'pre-Movement', [true, true, false]],
    ['amber', 'protected-clearance', [false, true, false]],
    ['green', 'protected-Movement-Allowed', [false, false, true]],
    ['dark', 'dark', [false, false, false]],
    ['unavailable', 'unavailable', [false, false, false]],
  ];
  for (const [state, eventState, lit] of cases) {
    const m = createModel();
    selectStation(m, '1');
    assert.equal(handleMessage(m, 'its/1/app/signal', signal({ state, event_state: eventState }), 0), 'signal', state);
    const p = signalPanel(m, 0);
    assert.equal(p.state, state);
    assert.deepEqual([p.red, p.amber, p.green], lit, state);
  }
});

test('signal panel: countdown in whole seconds, likely else minimum, running on between messages', () => {
  const m = createModel();
  selectStation(m, '1');
  handleMessage(m, 'its/1/app/signal', signal(), 0);
  assert.equal(signalPanel(m, 0).countdown, '8 s'); // likely 7.4 s, rounded up
  assert.equal(signalPanel(m, 0).countdownIsLikely, true);
  assert.equal(signalPanel(m, 500).countdown, '7 s'); // 6.9 s left half a second later
  handleMessage(m, 'its/1/app/signal', signal({ likely_time_to_change_s: null }), 600);
  assert.equal(signalPanel(m, 600).countdown, '7 s'); // the minimum, 6.2 s
  handleMessage(m, 'its/1/app/signal', signal({ time_to_change_s: -0.4, likely_time_to_change_s: undefined }), 700);
  assert.equal(signalPanel(m, 700).countdown, '0 s'); // due already: 0, never negative
  handleMessage(m, 'its/1/app/signal', signal({ time_to_change_s: null, likely_time_to_change_s: null }), 800);
  assert.equal(signalPanel(m, 800).countdown, '');
});

test('signal panel: distance, advice, caption', () => {
  const m = createModel();
  selectStation(m, '1');
  handleMessage(m, 'its/1/app/signal', signal({ advice: { min_speed_kmh: 31.4, max_speed_kmh: 48.9 } }), 0);
  const p = signalPanel(m, 0);
  assert.equal(p.distance, '42 m');
  assert.equal(p.advice, '32–48 km/h');
  assert.equal(p.caption, 'group 3 · lane 2');
  handleMessage(m, 'its/1/app/signal', signal({ advice: { min_speed_kmh: 40.2, max_speed_kmh: 40.8 } }), 0);
  assert.equal(signalPanel(m, 0).advice, '41 km/h');
  handleMessage(m, 'its/1/app/signal', signal(), 0);
  assert.equal(signalPanel(m, 0).advice, '');
});

test('signal panel: fresh for a second, gone after "lane": null, other stations ignored', () => {
  const m = createModel();
  selectStation(m, '1');
  handleMessage(m, 'its/1/app/signal', signal(), 0);
  assert.notEqual(signalPanel(m, SIGNAL_TIMEOUT_MS), null);
  assert.equal(signalPanel(m, SIGNAL_TIMEOUT_MS + 1), null);
  assert.equal(expire(m, SIGNAL_TIMEOUT_MS + 1), true);
  assert.equal(m.signal, null);
  handleMessage(m, 'its/1/app/signal', signal(), 2000);
  assert.equal(handleMessage(m, 'its/1/app/signal', env('signal', { lane: null }), 2100), 'signal');
  assert.equal(signalPanel(m, 2100), null);
  assert.equal(handleMessage(m, 'its/2/app/signal', signal(), 2200), null);
  assert.equal(signalPanel(m, 2200), null);
});

test('malformed signal and RLVW messages are counted and change nothing', () => {
  const m = createModel();
  selectStation(m, '1');
  handleMessage(m, 'its/1/app/signal', signal({ state: 'green', event_state: 'protected-Movement-Allowed' }), 0);
  handleMessage(m, 'its/1/app/rlvw', rlvw('raised'), 0);
  const badSignals = [
    { state: 'purple' }, { state: 3 }, { event_state: 'stop-and-remain' }, { intersection_id: 70000 },
    { intersection_id: '1' }, { signal_group: 256 }, { lane_id: 1.5 }, { time_to_change_s: 'soon' },
    { time_to_change_s: undefined }, { likely_time_to_change_s: [] }, { distance_to_stop_line_m: null },
    { advice: { min_speed_kmh: 50, max_speed_kmh: 30 } }, { advice: 42 }, { rlvw: 'yes' },
  ];
  for (const over of badSignals) {
    assert.equal(handleMessage(m, 'its/1/app/signal', signal(over), 10), null, JSON.stringify(over));
  }
  assert.equal(handleMessage(m, 'its/1/app/signal', env('signal', 'red'), 10), null);
  const badRlvw = [{ event: 'exploded' }, { signal_group: 300 }, { speed_mps: -1 }, { time_to_red_s: 'now' }, { lane_id: null }];
  for (const over of badRlvw) {
    assert.equal(handleMessage(m, 'its/1/app/rlvw', rlvw('updated', over), 10), null, JSON.stringify(over));
  }
  assert.equal(m.rejected, badSignals.length + 1 + badRlvw.length);
  assert.match(m.lastError, /^its\/1\/app\/rlvw: message\.lane_id/);
  assert.equal(signalPanel(m, 20).state, 'green');
  assert.equal(rlvwBanner(m, 20).when, 'red in 1.0 s');
});

test('RLVW: raised, cleared only by its own group, held by the signal flag, expired', () => {
  const m = createModel();
  selectStation(m, '1');
  assert.equal(handleMessage(m, 'its/1/app/rlvw', rlvw('raised', { time_to_red_s: 1.2 }), 0), 'rlvw');
  assert.deepEqual(rlvwBanner(m, 100), { when: 'red in 1.1 s', distance: '40 m', speed: '60 km/h' });
  handleMessage(m, 'its/1/app/rlvw', rlvw('updated', { time_to_red_s: null }), 200);
  assert.equal(rlvwBanner(m, 200).when, 'red');
  handleMessage(m, 'its/1/app/rlvw', rlvw('cleared', { signal_group: 4 }), 300);
  assert.notEqual(rlvwBanner(m, 300), null);
  handleMessage(m, 'its/1/app/rlvw', rlvw('cleared'), 400);
  assert.equal(rlvwBanner(m, 400), null);
  // Not refreshed: gone after the timeout unless the lane signal still says rlvw.
  handleMessage(m, 'its/1/app/rlvw', rlvw('raised'), 1000);
  handleMessage(m, 'its/1/app/signal', signal({ rlvw: true }), 1000 + RLVW_TIMEOUT_MS);
  assert.notEqual(rlvwBanner(m, 1000 + RLVW_TIMEOUT_MS + 500), null);
  assert.equal(expire(m, 1000 + RLVW_TIMEOUT_MS + 500), false);
  assert.equal(expire(m, 1000 + RLVW_TIMEOUT_MS + SIGNAL_TIMEOUT_MS + 1), true);
  assert.equal(rlvwBanner(m, 1000 + RLVW_TIMEOUT_MS + SIGNAL_TIMEOUT_MS + 1), null);
  // Changing the station forgets both.
  handleMessage(m, 'its/1/app/rlvw', rlvw('raised'), 5000);
  handleMessage(m, 'its/1/app/signal', signal(), 5000);
  selectStation(m, '2');
  assert.equal(signalPanel(m, 5000), null);
  assert.equal(rlvwBanner(m, 5000), null);
});
