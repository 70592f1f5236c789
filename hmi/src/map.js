// The live map: the own car at the centre, north up, neighbours placed by their CAM positions.
import { offsetM } from './etsi.js';

const RINGS_M = [25, 50, 100];

function drawCar(ctx, x, y, headingDeg, lengthM, widthM, scale, fill, label) {
  ctx.save();
  ctx.translate(x, y);
  // Canvas y grows downwards; ETSI heading is clockwise from north, as canvas rotation is.
  ctx.rotate(((headingDeg ?? 0) * Math.PI) / 180);
  const l = Math.max((lengthM ?? 4.5) * scale, 10);
  const w = Math.max((widthM ?? 1.8) * scale, 5);
  ctx.fillStyle = fill;
  ctx.strokeStyle = '#111';
  ctx.lineWidth = 1;
  ctx.fillRect(-w / 2, -l / 2, w, l);
  ctx.strokeRect(-w / 2, -l / 2, w, l);
  // Windscreen mark: which end is the front.
  ctx.fillStyle = 'rgba(255,255,255,0.85)';
  ctx.fillRect(-w / 2 + 1, -l / 2 + 1, w - 2, Math.max(l * 0.18, 2));
  ctx.restore();
  if (label) {
    ctx.fillStyle = '#e8e8e8';
    ctx.font = '12px sans-serif';
    ctx.fillText(label, x + 8, y - 8);
  }
}

export function drawMap(canvas, model) {
  const ctx = canvas.getContext('2d');
  const dpr = window.devicePixelRatio || 1;
  const cssW = canvas.clientWidth;
  const cssH = canvas.clientHeight;
  if (canvas.width !== Math.round(cssW * dpr) || canvas.height !== Math.round(cssH * dpr)) {
    canvas.width = Math.round(cssW * dpr);
    canvas.height = Math.round(cssH * dpr);
  }
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  ctx.fillStyle = '#1b1f24';
  ctx.fillRect(0, 0, cssW, cssH);
  const cx = cssW / 2;
  const cy = cssH / 2;
  // The largest ring fits the shorter side.
  const scale = (Math.min(cssW, cssH) / 2 - 10) / RINGS_M[RINGS_M.length - 1];

  ctx.strokeStyle = '#3a4250';
  ctx.fillStyle = '#7d8796';
  ctx.font = '11px sans-serif';
  for (const r of RINGS_M) {
    ctx.beginPath();
    ctx.arc(cx, cy, r * scale, 0, 2 * Math.PI);
    ctx.stroke();
    ctx.fillText(`${r} m`, cx + 3, cy - r * scale + 12);
  }
  ctx.fillText('N ↑', 8, 16);

  const own = model.own;
  if (!own || own.lat === null || own.lon === null) {
    ctx.fillStyle = '#c0c6cf';
    ctx.font = '14px sans-serif';
    ctx.fillText(model.station === null ? 'Choose a station' : 'Waiting for position…', 12, cssH - 14);
    return;
  }
  for (const [id, n] of model.neighbours) {
    if (n.lat === null || n.lon === null) {
      continue;
    }
    const d = offsetM(own.lat, own.lon, n.lat, n.lon);
    const x = cx + d.east * scale;
    const y = cy - d.north * scale;
    const atRisk = model.warnings.has(id);
    drawCar(ctx, x, y, n.heading, n.length, n.width, scale, atRisk ? '#ff3030' : '#4aa3ff', id);
  }
  drawCar(ctx, cx, cy, own.heading, own.length, own.width, scale, '#f5c400', null);
}
