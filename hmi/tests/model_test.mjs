// Unit tests of the HMI's model (pure JS, no browser): `node --test hmi/tests/model_test.mjs`.
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { causeText, offsetM } from '../src/etsi.js';
import {
  createModel,
  expire,
  formatTtc,
  handleMessage,
  selectStation,
  subscriptions,
  topWarning,
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
  handleMessage(m, 'its/1/app/lcrw', lcrw(3, 'cleared', null), 100);
  assert.equal(topWarning(m).other_station_id, 2);
  assert.equal(expire(m, WARNING_TIMEOUT_MS - 1), false);
  assert.equal(expire(m, WARNING_TIMEOUT_MS + 1), true);
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
