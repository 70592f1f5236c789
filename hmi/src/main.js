// The driver's HMI: wiring between MQTT over WebSockets, the model and the page.
import mqtt from 'mqtt';

import { beep, beepCount, audioState, prepareAudio, redLightBeep, redLightBeepCount, unlockAudio } from './audio.js';
import { causeText, fixText, offsetM } from './etsi.js';
import { drawMap } from './map.js';
import { denmReceipt, lcrwReceipt, signalReceipt, traceTopic } from './trace.js';
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
} from './model.js';

const $ = (id) => document.getElementById(id);

// Served by Mosquitto's http_dir on its WebSocket listener, the page finds the broker at its own
// address; ?broker=, ?user=, ?password=, ?station=, ?prefix= override (and are remembered);
// ?trace=1 reports the receipt of LCRW messages and DENMs (trace.js), for this page load only.
function settings() {
  const q = new URLSearchParams(location.search);
  const saved = JSON.parse(localStorage.getItem('hmi.settings') || '{}');
  const scheme = location.protocol === 'https:' ? 'wss' : 'ws';
  const sameHost = location.host ? `${scheme}://${location.host}/` : 'ws://127.0.0.1:9001/';
  return {
    broker: q.get('broker') ?? saved.broker ?? sameHost,
    user: q.get('user') ?? saved.user ?? 'hmi',
    password: q.get('password') ?? saved.password ?? 'hmi',
    station: q.get('station') ?? saved.station ?? null,
    prefix: q.get('prefix') ?? saved.prefix ?? 'its',
    trace: q.get('trace') === '1',
  };
}

// performance.now() is monotonic and sub-millisecond; with timeOrigin it is wall-clock time.
function wallClockMs() {
  return performance.timeOrigin + performance.now();
}

const cfg = settings();
const model = createModel(cfg.prefix);
let client = null;
let subscribed = [];
let lastBeep = 0;
let loggedRejects = 0;
let tracedSignal = '';

function save() {
  const { trace, ...kept } = cfg;
  localStorage.setItem('hmi.settings', JSON.stringify(kept));
}

function setConnection(state, detail = '') {
  const el = $('conn');
  el.dataset.state = state;
  el.textContent = { connected: 'Connected', connecting: 'Connecting…', reconnecting: 'Reconnecting…', offline: 'Offline', error: 'Error' }[state] + (detail ? ` — ${detail}` : '');
}

function resubscribe() {
  if (!client) {
    return;
  }
  const want = subscriptions(model);
  const drop = subscribed.filter((t) => !want.includes(t));
  if (drop.length) {
    client.unsubscribe(drop);
  }
  const add = want.filter((t) => !subscribed.includes(t));
  if (add.length) {
    client.subscribe(add, { qos: 1 });
  }
  subscribed = want;
}

function connect() {
  if (client) {
    client.end(true);
  }
  subscribed = [];
  setConnection('connecting');
  client = mqtt.connect(cfg.broker, {
    username: cfg.user,
    password: cfg.password,
    reconnectPeriod: 2000,
    connectTimeout: 5000,
    clean: true,
  });
  client.on('connect', () => {
    setConnection('connected', cfg.broker);
    subscribed = [];
    resubscribe();
  });
  client.on('reconnect', () => setConnection('reconnecting'));
  client.on('offline', () => setConnection('offline'));
  client.on('error', (e) => setConnection('error', e.message));
  client.on('message', (topic, payload) => {
    const receivedMs = wallClockMs();
    const text = payload.toString();
    const what = handleMessage(model, topic, text);
    if (what) {
      render(what);
    }
    if (cfg.trace && what === 'signal') {
      const r = signalReceipt(cfg.prefix, topic, text, receivedMs, wallClockMs());
      if (r && r.key !== tracedSignal) {
        tracedSignal = r.key;
        client.publish(traceTopic(cfg.prefix, model.station), r.record, { qos: 0 });
      }
    }
    if (cfg.trace && (what === 'warning' || what === 'denm')) {
      const receipt = what === 'warning' ? lcrwReceipt : denmReceipt;
      const record = receipt(cfg.prefix, topic, text, receivedMs, wallClockMs());
      if (record) {
        client.publish(traceTopic(cfg.prefix, model.station), record, { qos: 0 });
      }
    }
  });
}

function chooseStation(id) {
  selectStation(model, id || null);
  cfg.station = model.station;
  save();
  resubscribe();
  render('all');
}

function renderStations() {
  const sel = $('station');
  const ids = [...model.stations.keys()].sort((a, b) => Number(a) - Number(b));
  if (model.station !== null && !ids.includes(model.station)) {
    ids.push(model.station);
  }
  const current = [...sel.options].map((o) => o.value).join(',');
  if (current !== ['', ...ids].join(',')) {
    sel.replaceChildren(new Option('— choose a station —', ''), ...ids.map((id) => new Option(`Station ${id}`, id)));
  }
  sel.value = model.station ?? '';
  const st = model.station !== null ? model.stations.get(model.station) : null;
  const el = $('station-online');
  if (!st || st.online === null) {
    el.textContent = '';
    el.dataset.state = '';
  } else {
    el.textContent = st.online ? 'station online' : 'station offline';
    el.dataset.state = st.online ? 'online' : 'offline';
    if (st.dropped > 0) {
      el.textContent += ` · ${st.dropped} warnings lost`;
    }
  }
}

function renderOwn() {
  const own = model.own;
  $('speed').textContent = own?.speed != null ? (own.speed * 3.6).toFixed(0) : '–';
  $('heading').textContent = own?.heading != null ? `${own.heading.toFixed(0)}°` : '–';
  const fix = own ? own.fix : null;
  $('fix').textContent = fix ? fixText(fix) + (own.satellites != null ? ` · ${own.satellites} sats` : '') : '–';
  $('fix').dataset.fix = fix ?? '';
}

function renderWarning() {
  const w = topWarning(model);
  const banner = $('lcrw-banner');
  if (!w) {
    banner.hidden = true;
    document.body.classList.remove('alarm');
    return;
  }
  banner.hidden = false;
  banner.dataset.severity = w.severity;
  document.body.classList.add('alarm');
  $('lcrw-ttc').textContent = formatTtc(w.ttc_s);
  $('lcrw-case').textContent = w.collision_case === 'frontal' ? 'Head-on collision risk' : 'Rear-end collision risk';
  $('lcrw-detail').textContent =
    `vehicle ${w.other_station_id} · ${w.distance_m != null ? w.distance_m.toFixed(0) : '–'} m · closing ${w.relative_speed_mps != null ? (w.relative_speed_mps * 3.6).toFixed(0) : '–'} km/h`;
  sound();
}

// One alarm at a time, by priority (as the sim-client's v2x::alarm_for): a critical collision
// warning, then the red light (its own double beep every 600 ms), then a collision warning.
function sound() {
  const w = topWarning(model);
  const now = performance.now();
  if (w && w.severity === 'critical') {
    if (now - lastBeep >= 500) {
      lastBeep = now;
      beep(true);
    }
  } else if (rlvwBanner(model)) {
    if (now - lastBeep >= 600) {
      lastBeep = now;
      redLightBeep();
    }
  } else if (w && now - lastBeep >= 1000) {
    lastBeep = now;
    beep(false);
  }
}

// Sets an element's text only when it changes (the panel is refreshed every frame).
function setText(id, text) {
  const el = $(id);
  if (el.textContent !== text) {
    el.textContent = text;
  }
}

function renderSignal() {
  const p = signalPanel(model);
  const panel = $('signal-panel');
  if (!p) {
    panel.hidden = true;
    panel.dataset.state = '';
    return;
  }
  panel.hidden = false;
  panel.dataset.state = p.state;
  panel.classList.toggle('lit-red', p.red);
  panel.classList.toggle('lit-amber', p.amber);
  panel.classList.toggle('lit-green', p.green);
  setText('signal-caption', p.caption);
  setText('signal-countdown', p.countdown || '–');
  setText('signal-distance', `${p.distance} to stop line`);
  $('signal-advice-label').hidden = !p.advice;
  setText('signal-advice', p.advice);
}

function renderRlvw() {
  const b = rlvwBanner(model);
  const banner = $('rlvw-banner');
  if (!b) {
    banner.hidden = true;
    return;
  }
  banner.hidden = false;
  setText('rlvw-when', b.when);
  setText('rlvw-detail', `stop line ${b.distance} · ${b.speed}`);
  sound();
}

function renderDenms() {
  const list = $('denm-list');
  if (model.denms.length === 0) {
    list.replaceChildren(Object.assign(document.createElement('li'), { className: 'empty', textContent: 'No events' }));
    return;
  }
  list.replaceChildren(
    ...model.denms.map((d) => {
      const li = document.createElement('li');
      li.dataset.cause = d.cause;
      // The event's action ID and direction, for tests and tools (hmi/tools/headless_hmi.mjs).
      if (d.originator != null && d.seq != null) {
        li.dataset.originator = d.originator;
        li.dataset.seq = d.seq;
      }
      li.dataset.direction = d.direction;
      li.classList.toggle('terminated', d.terminated);
      let where = '';
      if (model.own?.lat != null && d.lat != null) {
        const o = offsetM(model.own.lat, model.own.lon, d.lat, d.lon);
        where = ` · ${Math.hypot(o.east, o.north).toFixed(0)} m away`;
      }
      const time = new Date(d.receivedAt).toLocaleTimeString();
      li.textContent = `${time} ${causeText(d.cause, d.subcause)} — ${d.direction === 'out' ? 'sent by this car' : `from station ${d.originator}`}${where}${d.terminated ? ' (ended)' : ''}`;
      return li;
    }),
  );
}

function render(what) {
  if (what === 'stations' || what === 'all') {
    renderStations();
  }
  if (what === 'own' || what === 'all') {
    renderOwn();
    renderStations();
  }
  if (what === 'warning' || what === 'all') {
    renderWarning();
  }
  if (what === 'denm' || what === 'all') {
    renderDenms();
  }
  if (what === 'signal' || what === 'all') {
    renderSignal();
    renderRlvw(); // the signal's rlvw flag holds the banner
  }
  if (what === 'rlvw' || what === 'all') {
    renderRlvw();
  }
}

function frame() {
  if (expire(model)) {
    renderWarning();
    renderRlvw();
  }
  if (model.warnings.size > 0) {
    renderWarning(); // keeps the beep going
  }
  // The countdown runs on between signal messages; the red-light beep goes on too.
  renderSignal();
  if (model.rlvw) {
    renderRlvw();
  }
  if (model.rejected !== loggedRejects) {
    // The first bad signal or RLVW message, then every 1000th, as the sim-client logs them.
    if (loggedRejects === 0 || Math.floor(model.rejected / 1000) !== Math.floor(loggedRejects / 1000)) {
      console.warn(`ignored message (${model.rejected} so far): ${model.lastError}`);
    }
    loggedRejects = model.rejected;
  }
  drawMap($('map'), model);
  $('sound').textContent = audioState() === 'running' ? 'Sound on' : 'Tap for sound';
  requestAnimationFrame(frame);
}

function init() {
  $('station').addEventListener('change', (e) => chooseStation(e.target.value));
  prepareAudio();
  $('sound').addEventListener('click', () => unlockAudio());
  document.addEventListener('pointerdown', () => unlockAudio(), { once: true });
  document.addEventListener('keydown', () => unlockAudio(), { once: true });
  const form = $('settings-form');
  form.broker.value = cfg.broker;
  form.user.value = cfg.user;
  form.password.value = cfg.password;
  form.addEventListener('submit', (e) => {
    e.preventDefault();
    cfg.broker = form.broker.value.trim();
    cfg.user = form.user.value;
    cfg.password = form.password.value;
    save();
    connect();
  });
  if (cfg.station !== null) {
    selectStation(model, cfg.station);
  }
  render('all');
  connect();
  requestAnimationFrame(frame);
  // For tests and debugging in the browser console.
  window.__hmi = { model, beepCount, redLightBeepCount, audioState };
}

init();
