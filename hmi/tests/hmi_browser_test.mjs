// Integration: the HMI in headless Chromium against a real Mosquitto configured by
// docker/mosquitto/gen-broker-config, serving hmi/dist on its WebSocket listener. A station
// (mqtt.js over TCP, with its generated credentials) publishes state, a CAM, a DENM, an LCRW
// warning, the own lane's signal and a red-light warning; the page must show them, the banner
// with the right TTC, the signal panel's lamps in the state's colours. Screenshots go to
// tests/artifacts/hmi/. Run via ctest (hmi.browser) or `node hmi/tests/hmi_browser_test.mjs`
// after hmi/build.sh.
import { spawn, spawnSync } from 'node:child_process';
import { existsSync, mkdirSync, mkdtempSync, readFileSync, rmSync } from 'node:fs';
import net from 'node:net';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

import mqtt from 'mqtt';
import { chromium } from 'playwright-core';

const here = dirname(fileURLToPath(import.meta.url));
const root = process.env.TESTBED_ROOT ?? resolve(here, '..', '..');
// HMI_DIST: another build of the page (ctest hmi.browser.debian: hmi/build.sh --debian).
const dist = process.env.HMI_DIST ? resolve(process.env.HMI_DIST) : join(root, 'hmi', 'dist');
const artifacts = join(root, 'tests', 'artifacts', 'hmi');
const CHROMIUM = process.env.CHROMIUM ?? '/usr/bin/chromium';

let passed = 0;
let failed = 0;
function check(name, ok, detail = '') {
  if (ok) {
    passed += 1;
    console.log(`ok - ${name}`);
  } else {
    failed += 1;
    console.log(`not ok - ${name}${detail ? `: ${detail}` : ''}`);
  }
}

function freePort() {
  return new Promise((res, rej) => {
    const s = net.createServer();
    s.once('error', rej);
    s.listen(0, '127.0.0.1', () => {
      const { port } = s.address();
      s.close(() => res(port));
    });
  });
}

async function waitForPort(port, ms) {
  const end = Date.now() + ms;
  while (Date.now() < end) {
    const ok = await new Promise((res) => {
      const c = net.connect(port, '127.0.0.1', () => { c.destroy(); res(true); });
      c.once('error', () => res(false));
    });
    if (ok) return true;
    await new Promise((r) => setTimeout(r, 50));
  }
  return false;
}

const envelope = (type, message) => JSON.stringify({ type, origin: 'self', version: '1.0.0', source_uuid: 'station-1001', timestamp: Date.now(), message });

async function main() {
  if (!existsSync(join(dist, 'index.html'))) {
    throw new Error(`${dist}/index.html missing: run hmi/build.sh first`);
  }
  if (!existsSync(CHROMIUM)) {
    throw new Error(`${CHROMIUM} not found: install Debian's chromium (scripts/install-deps)`);
  }
  mkdirSync(artifacts, { recursive: true });
  const work = mkdtempSync(join(tmpdir(), 'hmi-browser-'));
  spawnSync('chmod', ['0777', work]); // mosquitto drops root for its own user
  const cleanups = [() => rmSync(work, { recursive: true, force: true })];
  try {
    const tcp = await freePort();
    const ws = await freePort();
    const gen = spawnSync(join(root, 'docker', 'mosquitto', 'gen-broker-config'), [
      '--stations', '1001,1002', '--out', join(work, 'broker'), '--bind', '127.0.0.1',
      '--tcp-port', String(tcp), '--ws-port', String(ws), '--http-dir', dist,
    ], { encoding: 'utf8' });
    if (gen.status !== 0) throw new Error(`gen-broker-config failed: ${gen.stderr}`);
    const creds = JSON.parse(readFileSync(join(work, 'broker', 'credentials.json'), 'utf8'));

    let broker = null;
    let brokerLog = '';
    const startBroker = async () => {
      broker = spawn('mosquitto', ['-c', join(work, 'broker', 'mosquitto.conf')], { stdio: ['ignore', 'ignore', 'pipe'] });
      broker.stderr.on('data', (d) => { brokerLog += d; });
      if (!(await waitForPort(tcp, 5000)) || !(await waitForPort(ws, 5000))) {
        throw new Error(`mosquitto did not start: ${brokerLog}`);
      }
    };
    const stopBroker = () => new Promise((res) => {
      if (!broker || broker.exitCode !== null) return res();
      broker.once('exit', () => res());
      broker.kill('SIGTERM');
    });
    cleanups.unshift(() => stopBroker());
    await startBroker();

    const page_url = `http://127.0.0.1:${ws}/index.html?trace=1`;
    const html = await fetch(page_url).then((r) => r.text()).catch((e) => String(e));
    check('broker serves the HMI over HTTP on the WebSocket listener', html.includes('lcrw-banner'));

    const station = await mqtt.connectAsync(`mqtt://127.0.0.1:${tcp}`, {
      username: creds.stations['1001'].username,
      password: creds.stations['1001'].password,
      clientId: 'station-1001-test',
    });
    cleanups.unshift(() => station.end(true));
    const pub = (topic, payload, opts = { qos: 1 }) => station.publishAsync(topic, payload, opts);
    await pub('its/1001/status', JSON.stringify({ online: true, dropped: 0, pending: 0, timestamp: Date.now() }), { qos: 1, retain: true });
    await pub('its/1001/state', envelope('state', {
      station_id: 1001,
      basic_container: { station_type: 5, reference_position: { latitude: 480000000, longitude: 110000000 } },
      high_frequency_container: { heading: 900, speed: 1389, drive_direction: 0, vehicle_length: 43, vehicle_width: 18 },
      gnss: { fix: '3d', satellites_used: 9 },
    }), { qos: 1, retain: true });

    const userData = mkdtempSync(join(tmpdir(), 'hmi-chromium-'));
    cleanups.push(() => rmSync(userData, { recursive: true, force: true }));
    const context = await chromium.launchPersistentContext(userData, {
      executablePath: CHROMIUM,
      headless: true,
      viewport: { width: 1100, height: 760 },
      args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
        '--disable-background-networking', '--disable-component-update', '--disable-sync',
        '--autoplay-policy=no-user-gesture-required'],
    });
    cleanups.unshift(() => context.close());
    const page = context.pages()[0] ?? (await context.newPage());
    const errors = [];
    page.on('pageerror', (e) => errors.push(String(e)));
    await page.goto(page_url);

    await page.waitForSelector('#conn[data-state="connected"]', { timeout: 10000 }).catch(() => {});
    check('page connects to the broker over WebSockets', (await page.getAttribute('#conn', 'data-state')) === 'connected',
      await page.textContent('#conn'));
    // The driver picks the car from the stations that announced themselves.
    await page.waitForSelector('#station option[value="1001"]', { state: 'attached', timeout: 10000 }).catch(() => {});
    check('station list offers the station', (await page.$('#station option[value="1001"]')) !== null);
    await page.selectOption('#station', '1001').catch(() => {});
    await page.waitForFunction(() => document.getElementById('speed').textContent === '50', null, { timeout: 10000 }).catch(() => {});
    check('speed shown in km/h', (await page.textContent('#speed')) === '50', await page.textContent('#speed'));
    check('heading shown', (await page.textContent('#heading')) === '90°', await page.textContent('#heading'));
    check('GNSS fix shown', (await page.textContent('#fix')).startsWith('3D fix'), await page.textContent('#fix'));
    check('station online shown', (await page.textContent('#station-online')).includes('online'));

    // A neighbour 40 m east, heading west, and its collision-risk DENM.
    await pub('its/1001/in/cam/1002', envelope('cam', {
      station_id: 1002, generation_delta_time: 1,
      basic_container: { station_type: 5, reference_position: { latitude: 480000000, longitude: 110005360 } },
      high_frequency_container: { heading: 2700, speed: 1389, drive_direction: 0, vehicle_length: 43, vehicle_width: 18 },
    }), { qos: 0 });
    await pub('its/1001/in/denm/1002', envelope('denm', {
      station_id: 1002,
      management_container: { action_id: { originating_station_id: 1002, sequence_number: 1 }, event_position: { latitude: 480000000, longitude: 110005360 } },
      situation_container: { event_type: { cause: 97, subcause: 1 } },
    }));
    await page.waitForFunction(() => document.getElementById('denm-list').textContent.includes('Collision risk'), null, { timeout: 10000 }).catch(() => {});
    check('DENM listed', (await page.textContent('#denm-list')).includes('Collision risk (longitudinal)'), await page.textContent('#denm-list'));
    const neighbours = await page.evaluate(() => window.__hmi.model.neighbours.size);
    check('neighbour from CAM on the map', neighbours === 1, `neighbours=${neighbours}`);

    check('no banner before a warning', await page.isHidden('#lcrw-banner'));
    // With ?trace=1 the page reports each warning's receipt (hmi/src/trace.js) where the
    // launcher's collector reads them, as the read-only HMI user.
    const collector = await mqtt.connectAsync(`mqtt://127.0.0.1:${tcp}`, { username: 'hmi', password: 'hmi', clientId: 'trace-collector' });
    cleanups.unshift(() => collector.end(true));
    const receipts = [];
    collector.on('message', (topic, payload) => receipts.push({ topic, text: payload.toString(), at: Date.now() }));
    await collector.subscribeAsync('its/+/hmi/trace', { qos: 0 });
    const parseReceipt = (r) => {
      try {
        return { ...r, record: JSON.parse(r.text), tsMs: Number(BigInt(r.text.match(/"ts":(\d+)/)[1]) / 1000000n) };
      } catch {
        return { ...r, record: null, tsMs: NaN };
      }
    };
    const receiptOf = (ev) => receipts.map(parseReceipt).find((r) => r.record?.ev === ev);

    // A second road event of the neighbour: listed with its originator and action ID, and with
    // ?trace=1 its receipt reported as hmi.denm (scripts/report's denm.hmi stage).
    const denmAt = Date.now();
    await pub('its/1001/in/denm/1002', envelope('denm', {
      station_id: 1002,
      management_container: { action_id: { originating_station_id: 1002, sequence_number: 2 }, event_position: { latitude: 480000000, longitude: 110005360 } },
      situation_container: { event_type: { cause: 97, subcause: 1 } },
    }));
    const second = '#denm-list li[data-originator="1002"][data-seq="2"]';
    await page.waitForSelector(second, { state: 'attached', timeout: 10000 }).catch(() => {});
    const secondText = (await page.$(second)) ? await page.textContent(second) : null;
    check('DENM on its/1001/in/denm/1002 listed with its originator and sequence number',
      secondText !== null && secondText.includes('from station 1002') && secondText.includes('Collision risk'),
      `${secondText} / list: ${await page.textContent('#denm-list')}`);
    for (let i = 0; i < 50 && !receiptOf('hmi.denm'); i++) {
      await new Promise((r) => setTimeout(r, 100));
    }
    const dr = receiptOf('hmi.denm');
    check('trace=1: the DENM\'s receipt reported on its/1001/hmi/trace',
      dr?.topic === 'its/1001/hmi/trace' && dr.record.station === 1001 && dr.record.origin === 1002 &&
      dr.record.seq === 2 && dr.record.dir === 'in' && dr.record.term === false,
      dr ? dr.text : `nothing received: ${JSON.stringify(receipts)}`);
    check('trace=1: DENM receipt stamped between publication and arrival at the collector, shown after it',
      dr !== undefined && dr.tsMs >= denmAt && dr.tsMs <= dr.at &&
      BigInt(dr.text.match(/"shown_ns":(\d+)/)?.[1] ?? '0') >= BigInt(dr.text.match(/"ts":(\d+)/)[1]),
      dr ? `ts ${dr.tsMs} published ${denmAt} collected ${dr.at}` : 'nothing received');
    const ownStateTime = Date.now() - 40;
    const otherStateTime = Date.now() - 60;
    const warning = (event, ttc) => envelope('lcrw_warning', {
      station_id: 1001, other_station_id: 1002, event, collision_case: 'frontal', severity: 'warning',
      clear_reason: event === 'cleared' ? 'risk_ended' : 'none', ttc_s: ttc, distance_m: 36.0,
      relative_speed_mps: 15.0, lateral_offset_m: 0.2, raised_at: Date.now(), updated_at: Date.now(),
      own_state_time: ownStateTime, other_state_time: otherStateTime,
    });
    const raisedAt = Date.now();
    await pub('its/1001/app/lcrw', warning('raised', 2.4));
    // LCRW refreshes an active warning at every evaluation; so does the test while it looks.
    const refresh = setInterval(() => { pub('its/1001/app/lcrw', warning('updated', 2.4)).catch(() => {}); }, 300);
    try {
      await page.waitForSelector('#lcrw-banner', { state: 'visible', timeout: 10000 }).catch(() => {});
      check('warning banner shown', await page.isVisible('#lcrw-banner'));
      check('banner shows the TTC', (await page.textContent('#lcrw-ttc')) === '2.4 s', await page.textContent('#lcrw-ttc'));
      check('banner names the case', (await page.textContent('#lcrw-case')).includes('Head-on'), await page.textContent('#lcrw-case'));
      check('banner names the other vehicle', (await page.textContent('#lcrw-detail')).includes('vehicle 1002'));
      await page.waitForFunction(() => window.__hmi.beepCount() > 0, null, { timeout: 5000 }).catch(() => {});
      check('audible alert played', (await page.evaluate(() => window.__hmi.beepCount())) > 0,
        `audio=${await page.evaluate(() => window.__hmi.audioState())}`);
      await page.screenshot({ path: join(artifacts, 'warning.png') });
    } finally {
      clearInterval(refresh);
    }
    for (let i = 0; i < 50 && !receiptOf('hmi.lcrw'); i++) {
      await new Promise((r) => setTimeout(r, 100));
    }
    const first = receiptOf('hmi.lcrw');
    const record = first?.record ?? null;
    const tsMs = first?.tsMs ?? NaN;
    check('trace=1: the receipt of the warning reported on its/1001/hmi/trace',
      first?.topic === 'its/1001/hmi/trace' && record?.ev === 'hmi.lcrw' && record.station === 1001 &&
      record.from === 1002 && record.event === 'raised' && record.own_ms === ownStateTime &&
      record.gdt === (((otherStateTime - 1072915200000) % 65536) + 65536) % 65536,
      first ? first.text : 'nothing received');
    check('trace=1: receipt stamped between publication and arrival at the collector',
      tsMs >= raisedAt && tsMs <= first.at && typeof record?.shown_ns === 'number',
      first ? `ts ${tsMs} published ${raisedAt} collected ${first.at}` : 'nothing received');

    await pub('its/1001/app/lcrw', warning('cleared', null));
    await page.waitForSelector('#lcrw-banner', { state: 'hidden', timeout: 10000 }).catch(() => {});
    check('banner cleared with the warning', await page.isHidden('#lcrw-banner'));
    await page.screenshot({ path: join(artifacts, 'cleared.png') });

    // Issue 34: the own lane's signal and the red-light warning (the MQTT contract's payloads).
    const signalMsg = (state, eventState, extra = {}) => envelope('signal', {
      intersection_id: 1, signal_group: 2, lane_id: 1, state, event_state: eventState,
      time_to_change_s: 3.6, likely_time_to_change_s: 4.2, distance_to_stop_line_m: 36.0,
      advice: { min_speed_kmh: 38.5, max_speed_kmh: 50.0 }, rlvw: false, ...extra,
    });
    check('no signal panel before a signal message', await page.isHidden('#signal-panel'));
    const lampColours = () => page.evaluate(() => [...document.querySelectorAll('#signal-panel .lamp')]
      .map((l) => getComputedStyle(l).backgroundColor));
    const states = [
      ['red', 'stop-And-Remain', ['rgb(255, 31, 26)', 'rgb(51, 51, 51)', 'rgb(51, 51, 51)']],
      ['red_amber', 'pre-Movement', ['rgb(255, 31, 26)', 'rgb(255, 184, 0)', 'rgb(51, 51, 51)']],
      ['amber', 'protected-clearance', ['rgb(51, 51, 51)', 'rgb(255, 184, 0)', 'rgb(51, 51, 51)']],
      ['green', 'protected-Movement-Allowed', ['rgb(51, 51, 51)', 'rgb(51, 51, 51)', 'rgb(26, 242, 77)']],
      ['dark', 'dark', ['rgb(107, 107, 112)', 'rgb(107, 107, 112)', 'rgb(107, 107, 112)']],
    ];
    for (const [state, eventState, want] of states) {
      // Published at 10 Hz as a station on an ingress lane does, until the page shows the state.
      const feed = setInterval(() => { pub('its/1001/app/signal', signalMsg(state, eventState), { qos: 0 }).catch(() => {}); }, 100);
      try {
        await page.waitForSelector(`#signal-panel[data-state="${state}"]`, { timeout: 10000 }).catch(() => {});
        const got = await lampColours();
        check(`signal panel lit for ${state}`, JSON.stringify(got) === JSON.stringify(want), JSON.stringify(got));
      } finally {
        clearInterval(feed);
      }
    }
    const feed = setInterval(() => { pub('its/1001/app/signal', signalMsg('amber', 'protected-clearance', { rlvw: true }), { qos: 0 }).catch(() => {}); }, 100);
    try {
      await page.waitForSelector('#signal-panel[data-state="amber"]', { timeout: 10000 }).catch(() => {});
      const countdown = await page.textContent('#signal-countdown');
      check('signal panel counts down from the likely time in whole seconds', countdown === '5 s' || countdown === '4 s', countdown);
      check('signal panel shows the distance to the stop line', (await page.textContent('#signal-distance')) === '36 m to stop line',
        await page.textContent('#signal-distance'));
      check('signal panel shows the speed advice', (await page.textContent('#signal-advice')) === '39–50 km/h'
        && await page.isVisible('#signal-advice-label'),
        await page.textContent('#signal-advice'));
      check('no red-light banner before a warning', await page.isHidden('#rlvw-banner'));
      const redBefore = await page.evaluate(() => window.__hmi.redLightBeepCount());
      await pub('its/1001/app/rlvw', envelope('rlvw_warning', {
        station_id: 1001, intersection_id: 1, signal_group: 2, lane_id: 1, event: 'raised', severity: 'warning',
        distance_to_stop_line_m: 36.0, speed_mps: 16.7, time_to_red_s: 1.2, stopping_distance_m: 63.1,
        clear_reason: 'none', raised_at: Date.now(), updated_at: Date.now(),
      }));
      await page.waitForSelector('#rlvw-banner', { state: 'visible', timeout: 10000 }).catch(() => {});
      check('red-light banner shown', await page.isVisible('#rlvw-banner'));
      check('red-light banner names the stop line and the speed', (await page.textContent('#rlvw-detail')) === 'stop line 36 m · 60 km/h',
        await page.textContent('#rlvw-detail'));
      await page.waitForFunction((n) => window.__hmi.redLightBeepCount() > n, redBefore, { timeout: 5000 }).catch(() => {});
      check('red-light sound played', (await page.evaluate(() => window.__hmi.redLightBeepCount())) > redBefore,
        `audio=${await page.evaluate(() => window.__hmi.audioState())}`);
      await page.screenshot({ path: join(artifacts, 'signal-rlvw.png') });
      await pub('its/1001/app/rlvw', envelope('rlvw_warning', {
        station_id: 1001, intersection_id: 1, signal_group: 2, lane_id: 1, event: 'cleared', severity: 'warning',
        distance_to_stop_line_m: 20.0, speed_mps: 16.7, time_to_red_s: null, stopping_distance_m: 63.1,
        clear_reason: 'passed', raised_at: Date.now(), updated_at: Date.now(),
      }));
      await page.waitForSelector('#rlvw-banner', { state: 'hidden', timeout: 10000 }).catch(() => {});
      check('red-light banner gone with cleared', await page.isHidden('#rlvw-banner'));
    } finally {
      clearInterval(feed);
    }
    await pub('its/1001/app/signal', envelope('signal', { lane: null }));
    await page.waitForSelector('#signal-panel', { state: 'hidden', timeout: 10000 }).catch(() => {});
    check('signal panel gone when the car leaves the lane', await page.isHidden('#signal-panel'));
    // ?trace=1: one hmi.signal record per light drawn (not one per message at 10 Hz).
    for (let i = 0; i < 30 && receipts.filter((r) => r.text.includes('"hmi.signal"') && r.text.includes('"light":""')).length === 0; i++) {
      await new Promise((r) => setTimeout(r, 100));
    }
    const lights = receipts.map(parseReceipt).filter((r) => r.record?.ev === 'hmi.signal').map((r) => r.record.light);
    check('trace=1: each light drawn reported once as hmi.signal',
      JSON.stringify(lights) === JSON.stringify(['red', 'red_amber', 'amber', 'green', 'dark', 'amber', '']), JSON.stringify(lights));

    // A phone in portrait: everything still on one screen, the banner readable.
    await pub('its/1001/app/lcrw', warning('raised', 1.2).replace('"severity":"warning"', '"severity":"critical"'));
    await page.setViewportSize({ width: 390, height: 844 });
    await page.waitForSelector('#lcrw-banner', { state: 'visible', timeout: 10000 }).catch(() => {});
    check('critical banner on a phone-sized screen', (await page.getAttribute('#lcrw-banner', 'data-severity')) === 'critical'
      && (await page.textContent('#lcrw-ttc')) === '1.2 s', await page.textContent('#lcrw-ttc'));
    await page.screenshot({ path: join(artifacts, 'phone-critical.png') });
    await page.setViewportSize({ width: 1100, height: 760 });

    // Connection status follows the broker: away, then back (mqtt.js retries every 2 s).
    station.end(true);
    await stopBroker();
    await page.waitForFunction(() => document.getElementById('conn').dataset.state !== 'connected', null, { timeout: 10000 }).catch(() => {});
    const away = await page.getAttribute('#conn', 'data-state');
    check('connection status shows the broker gone', away === 'offline' || away === 'reconnecting', away);
    await page.screenshot({ path: join(artifacts, 'broker-away.png') });
    await startBroker();
    await page.waitForSelector('#conn[data-state="connected"]', { timeout: 15000 }).catch(() => {});
    check('page reconnects when the broker returns', (await page.getAttribute('#conn', 'data-state')) === 'connected',
      await page.textContent('#conn'));
    check('no script errors in the page', errors.length === 0, errors.join('; '));
  } finally {
    for (const c of cleanups) {
      try { await c(); } catch { /* best effort */ }
    }
  }
}

try {
  await main();
} catch (e) {
  failed += 1;
  console.log(`not ok - setup: ${e.message}`);
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
