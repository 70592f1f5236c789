// Unit tests of the HMI's trace records (pure JS): `node --test hmi/tests/trace_test.mjs`.
import assert from 'node:assert/strict';
import { test } from 'node:test';

import { denmReceipt, generationDeltaTime, lcrwReceipt, nsString, signalReceipt, traceTopic } from '../src/trace.js';

const ITS_EPOCH = 1072915200000;

function lcrwPayload(message) {
  return JSON.stringify({ type: 'lcrw_warning', origin: 'on_board_application', version: '1.0.0', source_uuid: 'station-1001', timestamp: 0, message });
}

const warning = {
  station_id: 1001,
  other_station_id: 1002,
  event: 'raised',
  other_state_time: ITS_EPOCH + 70000,
  own_state_time: ITS_EPOCH + 70040,
};

test('GenerationDeltaTime as the station computes it (its_time.hpp)', () => {
  assert.equal(generationDeltaTime(ITS_EPOCH), 0);
  assert.equal(generationDeltaTime(ITS_EPOCH + 70000), 70000 - 65536);
  assert.equal(generationDeltaTime(1763770000123), (1763770000123 - ITS_EPOCH) % 65536);
  assert.equal(generationDeltaTime(ITS_EPOCH - 1), 65535);
});

test('wall-clock ms become exact ns strings', () => {
  assert.equal(nsString(1000.5), '1000500000');
  assert.equal(nsString(1763770000123.25), '1763770000123250000');
  assert.equal(nsString(7), '7000000');
  // A fraction that rounds up to a whole ms carries into the ms.
  assert.equal(nsString(5.9999999), '6000000');
});

test('an LCRW message becomes an hmi.lcrw record naming its publication', () => {
  const line = lcrwReceipt('its', 'its/1001/app/lcrw', lcrwPayload(warning), 1763770000123.5, 1763770000124.25);
  assert.ok(line.startsWith('{"ts":1763770000123500000,'), line);
  assert.ok(line.endsWith(',"shown_ns":1763770000124250000}'), line);
  const r = JSON.parse(line);
  assert.deepEqual(
    { proc: r.proc, ev: r.ev, station: r.station, from: r.from, gdt: r.gdt, own_ms: r.own_ms, event: r.event },
    { proc: 'hmi', ev: 'hmi.lcrw', station: 1001, from: 1002, gdt: 70000 - 65536, own_ms: ITS_EPOCH + 70040, event: 'raised' },
  );
});

test('anything else makes no record', () => {
  const at = [1, 2];
  assert.equal(lcrwReceipt('its', 'its/1001/state', lcrwPayload(warning), ...at), null);
  assert.equal(lcrwReceipt('its', 'other/1001/app/lcrw', lcrwPayload(warning), ...at), null);
  assert.equal(lcrwReceipt('its', 'its/1001/app/lcrw/x', lcrwPayload(warning), ...at), null);
  assert.equal(lcrwReceipt('its', 'its/1001/app/lcrw', '{not json', ...at), null);
  assert.equal(lcrwReceipt('its', 'its/1001/app/lcrw', 'null', ...at), null);
  for (const key of Object.keys(warning)) {
    const partial = { ...warning };
    delete partial[key];
    assert.equal(lcrwReceipt('its', 'its/1001/app/lcrw', lcrwPayload(partial), ...at), null, key);
  }
  assert.equal(lcrwReceipt('its', 'its/1001/app/lcrw', lcrwPayload({ ...warning, other_state_time: 'x' }), ...at), null);
});

test('records go to the station\'s hmi/trace topic', () => {
  assert.equal(traceTopic('its', '1001'), 'its/1001/hmi/trace');
});

function denmPayload(actionId, extra = {}) {
  return JSON.stringify({
    type: 'denm', origin: 'self', version: '1.0.0', source_uuid: 'station-1002', timestamp: 0,
    message: {
      station_id: 1001,
      management_container: { action_id: actionId, event_position: { latitude: 1, longitude: 2 }, ...extra },
      situation_container: { event_type: { cause: 97, subcause: 1 } },
    },
  });
}

test('a received DENM becomes an hmi.denm record naming the topic\'s station and the action ID', () => {
  const line = denmReceipt('its', 'its/1002/in/denm/1001',
    denmPayload({ originating_station_id: 1001, sequence_number: 7 }), 1763770000123.5, 1763770000125);
  assert.ok(line.startsWith('{"ts":1763770000123500000,'), line);
  assert.ok(line.endsWith(',"shown_ns":1763770000125000000}'), line);
  const r = JSON.parse(line);
  assert.deepEqual(
    { proc: r.proc, ev: r.ev, station: r.station, origin: r.origin, seq: r.seq, dir: r.dir, term: r.term },
    { proc: 'hmi', ev: 'hmi.denm', station: 1002, origin: 1001, seq: 7, dir: 'in', term: false },
  );
});

test('the station\'s own DENM and a termination are told apart', () => {
  const own = JSON.parse(denmReceipt('its', 'its/1001/out/denm',
    denmPayload({ originating_station_id: 1001, sequence_number: 0 }, { termination: 0 }), 1, 2));
  assert.deepEqual([own.station, own.origin, own.seq, own.dir, own.term], [1001, 1001, 0, 'out', true]);
});

test('a DENM message without an action ID, or on another topic, makes no record', () => {
  const good = denmPayload({ originating_station_id: 1001, sequence_number: 7 });
  const at = [1, 2];
  assert.equal(denmReceipt('its', 'its/1002/in/denm', good, ...at), null);
  assert.equal(denmReceipt('its', 'its/1002/in/cam/1001', good, ...at), null);
  assert.equal(denmReceipt('its', 'its/1002/out/denm/x', good, ...at), null);
  assert.equal(denmReceipt('its', 'other/1002/in/denm/1001', good, ...at), null);
  assert.equal(denmReceipt('its', 'its/abc/in/denm/1001', good, ...at), null);
  assert.equal(denmReceipt('its', 'its/1002/in/denm/1001', '{not json', ...at), null);
  assert.equal(denmReceipt('its', 'its/1002/in/denm/1001', denmPayload({ originating_station_id: 1001 }), ...at), null);
  assert.equal(denmReceipt('its', 'its/1002/in/denm/1001', denmPayload({ sequence_number: 7 }), ...at), null);
  assert.equal(denmReceipt('its', 'its/1002/in/denm/1001', denmPayload({ originating_station_id: -1, sequence_number: 7 }), ...at), null);
});

test('a signal message becomes an hmi.signal record keyed by station, junction, group and state', () => {
  const payload = (message) => JSON.stringify({ type: 'signal', message });
  const sig = { intersection_id: 1, signal_group: 2, lane_id: 1, state: 'green', event_state: 'protected-Movement-Allowed', distance_to_stop_line_m: 30 };
  const r = signalReceipt('its', 'its/1001/app/signal', payload(sig), 1000.5, 1002.25);
  assert.equal(r.key, '1001/1/2/green');
  assert.equal(r.record, '{"ts":1000500000,"proc":"hmi","ev":"hmi.signal","station":1001,"intersection_id":1,"signal_group":2,"light":"green","shown_ns":1002250000}');
  assert.equal(signalReceipt('its', 'its/1001/app/signal', payload({ ...sig, state: 'amber' }), 0, 0).key, '1001/1/2/amber');
  const left = signalReceipt('its', 'its/1001/app/signal', payload({ lane: null }), 5, 6);
  assert.equal(left.key, '');
  assert.equal(JSON.parse(left.record).light, '');
  assert.equal(signalReceipt('its', 'its/1001/app/lcrw', payload(sig), 0, 0), null);
  assert.equal(signalReceipt('its', 'its/x/app/signal', payload(sig), 0, 0), null);
  assert.equal(signalReceipt('its', 'its/1001/app/signal', payload({ ...sig, signal_group: 'two' }), 0, 0), null);
  assert.equal(signalReceipt('its', 'its/1001/app/signal', 'not json', 0, 0), null);
});
