// The page's cursor readout and distance tool: a click picks the nearest drawn point under the
// cursor (within a few pixels of the ray through it, the nearest to the camera among those), shows
// its coordinates in the CRS's units with its class and intensity; with "measure" on, each click
// adds a vertex to a polyline whose segment and total lengths (3D and horizontal) are shown and
// which is drawn over the view.
import { basis, focalPx } from './camera.js';

const PICK_PX = 4;

// The ray through canvas pixel (px, py): origin (camera) and unit direction, grid frame.
function ray(cam, px, py, width, height) {
  const b = basis(cam), f = focalPx(cam, height), u = (px - 0.5 * width) / f, v = (0.5 * height - py) / f;
  const d = [0, 1, 2].map((i) => b.forward[i] + u * b.right[i] + v * b.up[i]);
  const len = Math.hypot(...d);
  return { o: [cam.x, cam.y, cam.z], d: d.map((x) => x / len), forward: b.forward };
}

// The nearest point to the camera among those within PICK_PX of the ray; null when none.
export function pick(renderer, cam, px, py) {
  const { width, height } = renderer.gl.canvas, r = ray(cam, px, py, width, height);
  const tol = PICK_PX / focalPx(cam, height);
  let best = null;
  for (const s of renderer.drawnSets()) {
    const p = s.pos;
    for (let i = 0; i < s.n; ++i) {
      const x = p[3 * i] - r.o[0], y = p[3 * i + 1] - r.o[1], z = p[3 * i + 2] - r.o[2];
      const t = x * r.d[0] + y * r.d[1] + z * r.d[2];
      if (t <= 0 || (best && t >= best.t)) continue;
      const ex = x - t * r.d[0], ey = y - t * r.d[1], ez = z - t * r.d[2];
      if (ex * ex + ey * ey + ez * ez > (tol * t) ** 2) continue;
      best = { t, x: p[3 * i], y: p[3 * i + 1], z: p[3 * i + 2], cls: s.cls[i], intensity: s.intensity[i] };
    }
  }
  return best;
}

// "X, Y, Z" in the CRS's units of a grid-frame point.
export function crsText(p, info) {
  const f = info.frame, o = info.origin_m;
  return `${((p.x + o[0]) / f.xy_to_metres).toFixed(2)}, ${((p.y + o[1]) / f.xy_to_metres).toFixed(2)}, ` +
    `${(p.z / f.z_to_metres).toFixed(2)}`;
}

// Lengths of the polyline in the CRS's units: 3D and horizontal, per segment and in all.
export function measureText(vertices, info) {
  if (vertices.length < 2) return vertices.length ? 'measure: click the next point' : 'measure: click a point';
  const f = info.frame;
  let total = 0, flat = 0;
  const parts = [];
  for (let i = 1; i < vertices.length; ++i) {
    const a = vertices[i - 1], b = vertices[i];
    const h = Math.hypot(b.x - a.x, b.y - a.y) / f.xy_to_metres, dz = (b.z - a.z) / f.z_to_metres;
    const d = Math.hypot(b.x - a.x, b.y - a.y, b.z - a.z) / f.xy_to_metres;
    total += d, flat += h;
    parts.push(`${d.toFixed(2)} (horizontal ${h.toFixed(2)}, dz ${dz.toFixed(2)})`);
  }
  return `measure: ${parts.join(' + ')}; total ${total.toFixed(2)}, horizontal ${flat.toFixed(2)} (CRS units)`;
}

// Draws the polyline on the 2D overlay canvas (pixels of the WebGL canvas, scaled to its size).
export function drawOverlay(overlay, cam, vertices, width, height) {
  overlay.width = width, overlay.height = height;
  const g = overlay.getContext('2d');
  g.clearRect(0, 0, width, height);
  if (!vertices.length) return;
  const b = basis(cam), f = focalPx(cam, height);
  const screen = vertices.map((v) => {
    const p = [v.x - cam.x, v.y - cam.y, v.z - cam.z];
    const depth = p[0] * b.forward[0] + p[1] * b.forward[1] + p[2] * b.forward[2];
    if (depth <= 0.1) return null;
    const x = 0.5 * width + f * (p[0] * b.right[0] + p[1] * b.right[1] + p[2] * b.right[2]) / depth;
    const y = 0.5 * height - f * (p[0] * b.up[0] + p[1] * b.up[1] + p[2] * b.up[2]) / depth;
    return [x, y];
  });
  g.strokeStyle = '#ffd23f', g.fillStyle = '#ffd23f', g.lineWidth = 2;
  g.beginPath();
  let open = false;
  for (const s of screen) {
    if (!s) { open = false; continue; }
    open ? g.lineTo(s[0], s[1]) : g.moveTo(s[0], s[1]);
    open = true;
  }
  g.stroke();
  for (const s of screen) if (s) g.fillRect(s[0] - 3, s[1] - 3, 6, 6);
}
