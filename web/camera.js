// The camera of `lidarscout render` (src/render/camera.cpp) in the page: position in metres
// from the survey's grid origin, yaw 0 = north (+y), pitch < 0 = down, vertical field of view;
// the same basis and clip-space matrix, so that a #camera=X,Y,Z,YAW,PITCH link shows what
// render shows for it.
const DEG = Math.PI / 180;

export function basis(cam) {
  const yaw = cam.yaw * DEG, pitch = cam.pitch * DEG;
  const forward = [Math.sin(yaw) * Math.cos(pitch), Math.cos(yaw) * Math.cos(pitch), Math.sin(pitch)];
  const right = [Math.cos(yaw), -Math.sin(yaw), 0];
  const up = [right[1] * forward[2] - right[2] * forward[1], right[2] * forward[0] - right[0] * forward[2],
              right[0] * forward[1] - right[1] * forward[0]];
  return { forward, right, up };
}

// Column-major (WebGL) view-projection for coordinates relative to the camera position.
export function viewProjection(cam, width, height) {
  const b = basis(cam);
  const t = Math.tan(0.5 * cam.fov * DEG), aspect = width / height, n = cam.near, f = cam.far;
  const rows = [b.right.map((v) => v / (t * aspect)), b.up.map((v) => v / t),
                b.forward.map((v) => v * (f + n) / (f - n)), b.forward];
  const m = new Float32Array(16);
  for (let r = 0; r < 4; ++r) for (let c = 0; c < 3; ++c) m[c * 4 + r] = rows[r][c];
  m[3 * 4 + 2] = -2 * f * n / (f - n);
  return m;
}

// The focal length in pixels (render::Camera::focal_px).
export function focalPx(cam, height) { return 0.5 * height / Math.tan(0.5 * cam.fov * DEG); }

// "X,Y,Z,YAW,PITCH" in the CRS's units -> a camera (metres from `origin`); null when malformed.
export function parseCamera(text, frame, origin) {
  const f = text.split(',').map((s) => s.trim());
  if (f.length !== 5 || f.some((s) => s === '' || !Number.isFinite(Number(s)))) return null;
  const [x, y, z, yaw, pitch] = f.map(Number);
  if (pitch < -90 || pitch > 90) return null;
  return { x: x * frame.xy_to_metres - origin[0], y: y * frame.xy_to_metres - origin[1], z: z * frame.z_to_metres,
           yaw, pitch, fov: 60, near: 0.1, far: 1e7 };
}

// The camera as #camera= takes it (CRS units), as render prints it.
export function cameraText(cam, frame, origin) {
  const x = (cam.x + origin[0]) / frame.xy_to_metres, y = (cam.y + origin[1]) / frame.xy_to_metres;
  const z = cam.z / frame.z_to_metres;
  const g = (v) => String(Number(v.toPrecision(6)));
  return `${x.toFixed(2)},${y.toFixed(2)},${z.toFixed(2)},${g(cam.yaw)},${g(cam.pitch)}`;
}

// Near and far planes that hold the box (metres, grid frame) seen from the camera: WebGL's depth
// buffer is 24-bit, so the far/near ratio must stay moderate.
export function fitDepthRange(cam, box) {
  const b = basis(cam);
  let lo = Infinity, hi = 0;
  for (let i = 0; i < 8; ++i) {
    const p = [i & 1 ? box[3] : box[0], i & 2 ? box[4] : box[1], i & 4 ? box[5] : box[2]];
    const d = (p[0] - cam.x) * b.forward[0] + (p[1] - cam.y) * b.forward[1] + (p[2] - cam.z) * b.forward[2];
    lo = Math.min(lo, d), hi = Math.max(hi, d);
  }
  const far = Math.max(hi * 1.05, 10), near = Math.max(0.5, Math.min(lo * 0.9, far / 1e4));
  return { near, far };
}
