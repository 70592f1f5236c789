// The audible alert: a WebAudio beep pattern while a warning is active. Browsers start audio
// only after a user gesture, so the page unlocks it on the first click or key.
let ctx = null;
let beeps = 0;
let redLightBeeps = 0;

export function unlockAudio() {
  const AC = window.AudioContext || window.webkitAudioContext;
  if (!AC) {
    return false;
  }
  ctx = ctx ?? new AC();
  if (ctx.state === 'suspended') {
    ctx.resume();
  }
  return true;
}

// Makes the audio context at page load (suspended until a gesture where the browser asks for
// one): made at the first warning instead, it held that warning's banner up for tens of ms.
export function prepareAudio() {
  const AC = window.AudioContext || window.webkitAudioContext;
  if (AC && !ctx) {
    ctx = new AC();
  }
}

export function audioState() {
  return ctx ? ctx.state : 'locked';
}

export function beepCount() {
  return beeps;
}

// The red-light warning's own sound (as the sim-client's, sim-client/v2x/warning_sound.hpp):
// two 90 ms 1.25 kHz beeps 60 ms apart, so that it is not mistaken for the collision warning.
export function redLightBeep() {
  if (tones(1250, 'sine', [0, 0.15], 0.09)) {
    redLightBeeps += 1;
  }
}

export function redLightBeepCount() {
  return redLightBeeps;
}

function tones(frequency, type, offsets, length) {
  if (!ctx) {
    unlockAudio();
  }
  if (!ctx) {
    return false;
  }
  const t0 = ctx.currentTime;
  for (const offset of offsets) {
    const osc = ctx.createOscillator();
    const gain = ctx.createGain();
    osc.type = type;
    osc.frequency.value = frequency;
    gain.gain.setValueAtTime(0.0001, t0 + offset);
    gain.gain.exponentialRampToValueAtTime(0.4, t0 + offset + 0.01);
    gain.gain.exponentialRampToValueAtTime(0.0001, t0 + offset + length - 0.01);
    osc.connect(gain).connect(ctx.destination);
    osc.start(t0 + offset);
    osc.stop(t0 + offset + length);
  }
  beeps += 1;
  return true;
}

// Two short 880 Hz tones; critical warnings use a higher, harsher tone.
export function beep(critical = false) {
  if (!ctx) {
    unlockAudio();
  }
  if (!ctx) {
    return;
  }
  const t0 = ctx.currentTime;
  for (const offset of [0, 0.18]) {
    const osc = ctx.createOscillator();
    const gain = ctx.createGain();
    osc.type = critical ? 'square' : 'sine';
    osc.frequency.value = critical ? 1320 : 880;
    gain.gain.setValueAtTime(0.0001, t0 + offset);
    gain.gain.exponentialRampToValueAtTime(0.4, t0 + offset + 0.01);
    gain.gain.exponentialRampToValueAtTime(0.0001, t0 + offset + 0.14);
    osc.connect(gain).connect(ctx.destination);
    osc.start(t0 + offset);
    osc.stop(t0 + offset + 0.15);
  }
  beeps += 1;
}
