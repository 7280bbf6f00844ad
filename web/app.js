// The page's main loop: opens the first survey of the server, places the camera from the URL
// fragment (#camera=X,Y,Z,YAW,PITCH in the CRS's units, or #camera=auto: render's auto camera,
// computed by the server), streams the chunk points cell by cell nearest the camera first, then
// the heightmap patches, and draws on demand. #colour=rgb|elevation|intensity|classification as
// render's --colour; #ui=0 hides the panel (screenshots); #measure=1 and
// #clicks=X,Y;X,Y click once everything in view is loaded (tests of the readout and distance tool). The page's
// timings (ms since navigation) are kept in #timings as JSON for tests and benchmarks.
import { Api } from './data.js';
import { basis, cameraText, fitDepthRange, focalPx, parseCamera, viewProjection } from './camera.js';
import { Renderer } from './gl.js';
import { crsText, drawOverlay, measureText, pick } from './tools.js';

const POINT_BATCH = 256, PATCH_BATCH = 16, IN_FLIGHT = 4, CHUNK_POINT_PX = 2, MAX_PATCHES = 4000;
const LEVELS = 4, TEXEL_M = 10, MAX_LOD_POINTS = 8e6;  // (a heightmap texel: what level 0 refines)
const MAX_CNN_PATCHES = 256;  // the network's heightmaps: the nearest cells only (inference is the cost)
const $ = (id) => document.getElementById(id);
const hash = new URLSearchParams(location.hash.slice(1));
const timings = {};
const mark = (name) => {  // (and a frame, which shows it in #timings)
  if (name in timings) return;
  timings[name] = Math.round(performance.now());
  state.dirty = true;
};

const state = {
  api: new Api(0), info: null, cam: null, box: null, mode: 0, dirty: true,
  cellCounts: new Map(),  // "ix,iy" -> points the server had when listed
  fetchedCounts: new Map(),  // "ix,iy" -> points received
  patchQueue: [], patchesAsked: new Set(), inFlight: 0, pointsReceived: 0, patches: 0,
  controller: new AbortController(), errors: 0, lastError: '',
  tiles: null, levelsAsked: [], lodPoints: 0, lodGeneration: 0, levelRequests: new Map(), levelsDropped: 0,
  measured: [], patchMethod: 'linear', cnnPatches: 0, retries: 0, emptyBatches: 0,
  detailQueue: [], detailTiles: new Set(), methodOf: new Map(), detailPatches: 0,
};

function cellCentre(key, size) {
  const [ix, iy] = key.split(',').map(Number);
  return [(ix + 0.5) * size, (iy + 0.5) * size];
}

// Nearest first, the cells in front of the camera before those behind it.
function byPriority(keys) {
  const size = state.info.patch_size_m, b = basis(state.cam), c = state.cam;
  const score = (k) => {
    const [x, y] = cellCentre(k, size), dx = x - c.x, dy = y - c.y;
    const ahead = dx * b.forward[0] + dy * b.forward[1] > -size;
    return Math.hypot(dx, dy) + (ahead ? 0 : 1e12);
  };
  return keys.map((k) => [score(k), k]).sort((a, b2) => a[0] - b2[0]).map((p) => p[1]);
}

function resize() {
  const canvas = $('view'), dpr = window.devicePixelRatio || 1;
  canvas.width = Math.round(canvas.clientWidth * dpr);
  canvas.height = Math.round(canvas.clientHeight * dpr);
  state.dirty = true;
  // #camera=auto frames the data for the image's shape, as render does for its size: again for the new one
  if (state.autoCamera && state.info) {
    state.api.autoCamera(canvas.width, canvas.height, 60).then((c) => {
      if (state.autoCamera) setCamera(fromServerCamera(c), false);
    }).catch(fail);
  }
}

function setCamera(cam, fromUser = true) {
  state.cam = { ...cam, ...fitDepthRange(cam, state.box) };
  state.dirty = true;
  if (fromUser) state.autoCamera = false, scheduleHashUpdate();
  if (state.tiles) dropUnwantedLevels();
}

let hashTimer = 0;
function scheduleHashUpdate() {
  clearTimeout(hashTimer);
  hashTimer = setTimeout(() => {
    hash.set('camera', cameraText(state.cam, state.info.frame, state.info.origin_m));
    history.replaceState(null, '', '#' + hash.toString().replaceAll('%2C', ','));
  }, 300);
}

async function initialCamera(w, h) {
  const text = hash.get('camera') || 'auto';
  state.autoCamera = text === 'auto';
  if (text !== 'auto') {
    const cam = parseCamera(text, state.info.frame, state.info.origin_m);
    if (cam) return cam;
    state.autoCamera = true;
    state.lastError = `bad #camera=${text}: X,Y,Z,YAW,PITCH or auto`;
  }
  return fromServerCamera(await state.api.autoCamera(w, h, 60));
}

function fromServerCamera(c) {
  return { x: c.x_m, y: c.y_m, z: c.z_m, yaw: c.yaw_deg, pitch: c.pitch_deg, fov: c.fov_deg, near: c.near_m,
           far: c.far_m };
}

// ---- streaming ---------------------------------------------------------------------------
// The loading's progress, then the cells: a list asked for after the server said it had loaded
// everything is complete (only then do the heightmaps start: a window needs its neighbours).
async function pollCells() {
  const info = await state.api.info();
  const cells = await state.api.cells();
  for (const c of cells) state.cellCounts.set(`${c.ix},${c.iy}`, c.n);
  state.info.loading = info.datasets[0].loading;
  if (info.datasets[0].intensity_range) state.info = { ...state.info, ...info.datasets[0] };
  state.cellsComplete = state.info.loading.finished;
  pump();
  if (!state.info.loading.finished) setTimeout(() => pollCells().catch(fail), 250);
}

function pendingPointCells() {
  const keys = [];
  for (const [k, n] of state.cellCounts) if ((state.fetchedCounts.get(k) ?? -1) < n) keys.push(k);
  return keys;
}

function pump() {
  while (state.inFlight < IN_FLIGHT) {
    const cells = byPriority(pendingPointCells().filter((k) => !state.asked?.has(k))).slice(0, POINT_BATCH);
    if (cells.length) { fetchPoints(cells); continue; }
    if (!state.cellsComplete) return;
    if (!state.patchQueue.length && state.patchesAsked.size === 0) startPatches();
    const patches = state.patchQueue.splice(0, PATCH_BATCH);
    if (patches.length) { fetchPatches(patches, state.patchMethod); continue; }
    if (state.patchMethod === 'linear' && state.info.cnn && state.inFlight === 0 && 'terrain' in timings) {
      state.patchMethod = 'cnn';  // then the network's, nearest first, over the linear ones
      state.patchQueue = byPriority([...state.patchesAsked]).slice(0, MAX_CNN_PATCHES);
      state.patchesDone = 0;
      continue;
    }
    const details = state.detailQueue.splice(0, PATCH_BATCH);
    if (details.length) { fetchDetail(details); continue; }
    const next = nextLevel();
    if (!next) {
      if (state.inFlight === 0 && state.tiles) mark('idle');  // everything the view wants is in
      return;
    }
    fetchLevel(next);
  }
}

// ---- full resolution: the levels of detail of the tiles near the camera ----------------------
// A tile's level L is wanted while the levels below it (or, for level 0, the heightmap's texels)
// are more than a pixel apart on screen, nearest tiles and coarser levels first, within a budget.
// The tile's distance from the camera when its level `level` is wanted from here, else null.
function levelWanted(i, level) {
  const t = state.tiles, c = state.cam, b = basis(c), focal = focalPx(c, state.renderer.gl.canvas.height);
  const box = t.boxes_dm.slice(6 * i, 6 * i + 6).map((v) => v / 10);
  const dx = Math.max(box[0] - c.x, 0, c.x - box[3]), dy = Math.max(box[1] - c.y, 0, c.y - box[4]);
  const dz = Math.max(box[2] - c.z, 0, c.z - box[5]), d = Math.max(1, Math.hypot(dx, dy, dz));
  const cx = 0.5 * (box[0] + box[3]) - c.x, cy = 0.5 * (box[1] + box[4]) - c.y;
  const radius = 0.5 * Math.hypot(box[3] - box[0], box[4] - box[1]);
  if (cx * b.forward[0] + cy * b.forward[1] + (0.5 * (box[2] + box[5]) - c.z) * b.forward[2] < -radius) return null;
  const spacing = Math.sqrt(Math.max(1, (box[3] - box[0]) * (box[4] - box[1])) / Math.max(1, t.points[i]));
  const coarser = level === 0 ? TEXEL_M : spacing * 2 ** (LEVELS - level);
  return coarser * focal / d > 1 ? d : null;
}

function nextLevel() {
  const t = state.tiles;
  if (!t || state.lodPoints >= MAX_LOD_POINTS) return null;
  let best = null;
  for (let i = 0; i < t.names.length; ++i) {
    const level = state.levelsAsked[i] ?? 0;
    if (level >= LEVELS) continue;
    const d = levelWanted(i, level);
    if (d === null) continue;
    const score = level * 1e9 + d;
    if (!best || score < best.score) best = { score, tile: i, level };
  }
  if (best) state.levelsAsked[best.tile] = best.level + 1;
  return best;
}

// The client moves on: the levels under way that the view no longer wants are aborted (the server
// then drops their decoding if it has not begun) and may be asked for again when they are wanted.
function dropUnwantedLevels(all = false) {
  for (const [key, r] of state.levelRequests) {
    if (!all && levelWanted(r.tile, r.level) !== null) continue;
    r.controller.abort();
    state.levelRequests.delete(key);
    if (!all) state.levelsAsked[r.tile] = Math.min(state.levelsAsked[r.tile] ?? 0, r.level);
    ++state.levelsDropped;
  }
}

// The server decoded tile `tile` whole for a level: its points now lie under the heightmaps of the
// cells it covers (render's overlay); those heightmaps again, with that detail.
function learnt(tile) {
  if (state.detailTiles.has(tile) || !state.tiles) return;
  state.detailTiles.add(tile);
  const box = state.tiles.boxes_dm.slice(6 * tile, 6 * tile + 6).map((v) => v / 10), size = state.info.patch_size_m;
  for (const key of state.patchesAsked) {
    const [ix, iy] = key.split(',').map(Number);
    const inside = (ix + 1) * size > box[0] && ix * size < box[3] && (iy + 1) * size > box[1] && iy * size < box[4];
    if (inside && !state.detailQueue.includes(key)) state.detailQueue.push(key);
  }
}

function fetchDetail(keys) {
  ++state.inFlight;
  const byMethod = new Map();
  for (const k of keys) {
    const m = state.methodOf.get(k) ?? 'linear';
    byMethod.set(m, [...(byMethod.get(m) ?? []), k]);
  }
  Promise.all([...byMethod].map(([method, ks]) =>
    state.api.heightmaps(toCells(ks), state.patchStep, method, state.controller.signal, true).then((maps) => {
      for (const m of maps ?? []) if (m.triangles) state.renderer.addPatch(m), ++state.detailPatches;
      mark('first_detail');
      state.dirty = true;
    }))).catch(fail).finally(() => { --state.inFlight; pump(); });
}

// The attributes the full-resolution points carry: those the colour mode draws, and the class for
// the class filter (the chunk points, few, carry all).
function levelAttributes() {
  return ['rgb565,class', 'class', 'intensity,class', 'class'][state.mode];
}

// A new colour mode: the levels of detail again, with its attributes.
function reloadLevels() {
  ++state.lodGeneration;
  dropUnwantedLevels(true);  // (those of the old colour mode)
  state.renderer.clearLevels();
  state.levelsAsked = [];
  state.lodPoints = 0;
  pump();
}

function fetchLevel({ tile, level }) {
  ++state.inFlight;
  const generation = state.lodGeneration, key = `${tile}/${level}`, controller = new AbortController();
  state.levelRequests.set(key, { tile, level, controller });
  state.controller.signal.addEventListener('abort', () => controller.abort());  // (the page left)
  state.api.level(tile, level, levelAttributes(), controller.signal).then((l) => {
    learnt(tile);
    if (generation !== state.lodGeneration) return;  // asked for another colour mode
    state.renderer.addLevel(l);
    const n = l.blocks.reduce((a, b) => a + b.n, 0);
    state.lodPoints += n;
    mark('first_full_res');
    state.dirty = true;
  }).catch(fail).finally(() => {
    if (state.levelRequests.get(key)?.controller === controller) state.levelRequests.delete(key);
    --state.inFlight;
    pump();
  });
}

function toCells(keys) { return keys.map((k) => { const [ix, iy] = k.split(',').map(Number); return { ix, iy }; }); }

function fetchPoints(keys) {
  state.asked ??= new Set();
  keys.forEach((k) => state.asked.add(k));
  ++state.inFlight;
  const attrs = 'rgb,class,intensity';  // (chunk points are few: all their attributes)
  state.api.points(toCells(keys), state.info.patch_size_m, attrs, state.controller.signal).then((cells) => {
    mark('first_points');
    for (const c of cells) {
      state.renderer.addCell(c);
      state.fetchedCounts.set(`${c.ix},${c.iy}`, c.n);
      state.pointsReceived += c.n;
      c.cls.forEach((v) => state.classesSeen.add(v));
    }
    updateClasses();
    state.dirty = true;
  }).catch(fail).finally(() => {
    keys.forEach((k) => state.asked.delete(k));
    --state.inFlight;
    if (state.cellsComplete && pendingPointCells().length === 0) mark('overview');
    pump();
  });
}

function startPatches() {
  state.patchQueue = byPriority([...state.cellCounts.keys()]).slice(0, MAX_PATCHES);
  state.patchQueue.forEach((k) => state.patchesAsked.add(k));
  state.patchStep = state.patchQueue.length > 600 ? 4 : 1;  // coarser meshes for a large survey
  if (!state.patchQueue.length) mark('terrain');
}

function fetchPatches(keys, method) {
  ++state.inFlight;
  const detail = state.detailTiles.size > 0;  // (what the decoded tiles taught the server, once there is some)
  state.api.heightmaps(toCells(keys), state.patchStep, method, state.controller.signal, detail).then((maps) => {
    if (maps === null) {  // the server still loads: again later
      ++state.retries;
      state.patchQueue.unshift(...keys);
      return;
    }
    state.patchesDone = (state.patchesDone ?? 0) + keys.length;
    for (const m of maps) {
      if (!m.triangles) continue;
      if (method === 'cnn') ++state.cnnPatches;
      else ++state.patches;
      state.methodOf.set(`${m.ix},${m.iy}`, method);
      state.renderer.addPatch(m);
    }
    if (maps.length) mark(method === 'cnn' ? 'first_cnn' : 'first_terrain');
    else ++state.emptyBatches;
    state.dirty = true;
  }).catch(fail).finally(() => {
    --state.inFlight;
    if (method === 'linear' && state.patchesDone >= state.patchesAsked.size) mark('terrain');
    pump();
  });
}

function fail(e) {
  if (e.name === 'AbortError') return;
  ++state.errors;
  state.lastError = e.message;
  console.error(e);
}

// ---- panel -------------------------------------------------------------------------------
function updateClasses() {
  const box = $('classes'), have = new Set([...box.querySelectorAll('input')].map((i) => Number(i.value)));
  for (const c of [...state.classesSeen].sort((a, b) => a - b)) {
    if (have.has(c)) continue;
    const label = document.createElement('label');
    label.innerHTML = `<input type="checkbox" value="${c}" checked> ${c}`;
    label.querySelector('input').addEventListener('change', applyClassFilter);
    box.appendChild(label);
  }
}

function applyClassFilter() {
  const visible = new Array(256).fill(true);
  for (const i of $('classes').querySelectorAll('input')) visible[Number(i.value)] = i.checked;
  state.renderer.setVisibleClasses(visible);
  state.dirty = true;
}

function fillTiles(tiles) {
  $('tile-count').textContent = tiles.names.length;
  const list = $('tiles');
  tiles.names.slice(0, 5000).forEach((name, i) => {
    const li = document.createElement('li');
    li.textContent = name;
    li.title = `${tiles.points[i].toLocaleString()} points`;
    li.addEventListener('click', async () => {
      const c = state.renderer.gl.canvas;
      setCamera(fromServerCamera(await state.api.autoCamera(c.width, c.height, 60, i)));
      pump();
    });
    list.appendChild(li);
  });
}

function progressLine(drawn) {
  const l = state.info.loading, mb = (state.api.bytes / 1048576).toFixed(1);
  const t = (k) => (k in timings ? `${(timings[k] / 1000).toFixed(2)} s` : '…');
  const received = state.pointsReceived + state.lodPoints;  // bytes of points sent (gzip'd) per point
  const perPoint = received ? (wirePointBytes() / received).toFixed(2) : '-';
  return `tiles ${l.tiles_done}/${state.info.tiles} · chunk points ${state.pointsReceived.toLocaleString()}` +
    ` · full-res ${state.lodPoints.toLocaleString()} (${drawn.toLocaleString()} drawn)` +
    ` · heightmaps ${state.patches}` +
    (state.info.cnn ? ` (network ${state.cnnPatches})` : '') +
    ` · ${mb} MB (points ${perPoint} B each)` +
    ` · overview ${t('overview')} · terrain ${t('first_terrain')}` +
    (state.errors ? ` · ${state.errors} errors: ${state.lastError}` : '') +
    (state.lastError && !state.errors ? ` · ${state.lastError}` : '');
}

// The bytes of point bodies as they came over the network (compressed), from the resource timings.
function wirePointBytes() {
  let n = 0;
  for (const e of performance.getEntriesByType('resource')) {
    if (/\/(points|level\/\d)(\?|$)/.test(new URL(e.name).pathname + '?')) n += e.encodedBodySize;
  }
  return n;
}

// ---- input -------------------------------------------------------------------------------
function moveBy(forward, right, up) {
  const b = basis(state.cam), c = state.cam;
  setCamera({ ...c, x: c.x + forward * b.forward[0] + right * b.right[0],
              y: c.y + forward * b.forward[1] + right * b.right[1],
              z: c.z + forward * b.forward[2] + up });
  pump();
}

function stepLength() {  // a tenth of the height above the data's lowest point, at least 5 m
  return Math.max(5, 0.1 * (state.cam.z - state.box[2]));
}

function bindInput(canvas) {
  let drag = null;
  canvas.addEventListener('contextmenu', (e) => e.preventDefault());
  canvas.addEventListener('pointerdown', (e) => {
    drag = { x: e.clientX, y: e.clientY, button: e.button, x0: e.clientX, y0: e.clientY };
  });
  window.addEventListener('pointerup', (e) => {
    const click = drag && drag.button === 0 && Math.hypot(e.clientX - drag.x0, e.clientY - drag.y0) < 3;
    drag = null;
    if (click) clickAt(e.clientX, e.clientY);
  });
  window.addEventListener('pointermove', (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX, drag.y = e.clientY;
    if (drag.button === 0) {
      setCamera({ ...state.cam, yaw: (state.cam.yaw + dx * 0.2 + 360) % 360,
                  pitch: Math.max(-90, Math.min(90, state.cam.pitch - dy * 0.2)) });
    } else {
      const s = stepLength() / 20;
      moveBy(dy * s, -dx * s, 0);
    }
  });
  canvas.addEventListener('wheel', (e) => { e.preventDefault(); moveBy(-Math.sign(e.deltaY) * stepLength(), 0, 0); },
                          { passive: false });
  window.addEventListener('keydown', (e) => {
    const s = stepLength(), k = e.key.toLowerCase();
    const moves = { w: [s, 0, 0], s: [-s, 0, 0], a: [0, -s, 0], d: [0, s, 0], q: [0, 0, -s], e: [0, 0, s] };
    if (moves[k]) moveBy(...moves[k]);
  });
  $('measure').addEventListener('change', () => {
    state.measured = [];
    $('measured').textContent = $('measure').checked ? measureText([], state.info) : '';
    state.dirty = true;
  });
  $('colour').addEventListener('change', (e) => {
    state.mode = Number(e.target.value);
    state.dirty = true;
    hash.set('colour', COLOUR_MODES[state.mode]);
    scheduleHashUpdate();
    reloadLevels();
  });
  window.addEventListener('resize', resize);
  window.addEventListener('pagehide', () => state.controller.abort());  // a client that leaves cancels its work
}

// A click: the readout of the point under the cursor, and a vertex of the measured line.
function clickAt(clientX, clientY) {
  const dpr = window.devicePixelRatio || 1, p = pick(state.renderer, state.cam, clientX * dpr, clientY * dpr);
  if (!p) {
    $('pick').textContent = 'no point under the cursor';
    return;
  }
  $('pick').textContent = `point ${crsText(p, state.info)} · class ${p.cls} · intensity ${p.intensity}`;
  if (!$('measure').checked) return;
  state.measured.push(p);
  $('measured').textContent = measureText(state.measured, state.info);
  state.dirty = true;
}

// #measure=1&clicks=X,Y;X,Y (CSS pixels): clicks made once everything the view wants is in (tests).
function scriptedClicks() {
  if (hash.get('measure') === '1') $('measure').checked = true;
  for (const xy of (hash.get('clicks') || '').split(';').filter(Boolean)) {
    const [x, y] = xy.split(',').map(Number);
    if (Number.isFinite(x) && Number.isFinite(y)) clickAt(x, y);
  }
}

// ---- frame -------------------------------------------------------------------------------
function frame() {
  if (state.dirty) {
    state.dirty = false;
    const canvas = state.renderer.gl.canvas, info = state.info;
    const grey = info.has_rgb === false ? info.uncoloured_grey / 255 : 0;
    const drawn = state.renderer.draw({
      cam: state.cam, vp: viewProjection(state.cam, canvas.width, canvas.height), mode: state.mode,
      zrange: [info.bounds_m[2], info.bounds_m[5]], irange: info.intensity_range ?? [0, 65535],
      pointSize: CHUNK_POINT_PX, uncoloured: grey, untextured: info.uncoloured_grey / 255,
      focal: focalPx(state.cam, canvas.height) });
    $('progress').textContent = progressLine(drawn);
    drawOverlay($('overlay'), state.cam, state.measured, canvas.width, canvas.height);
    $('readout').textContent = `camera ${cameraText(state.cam, info.frame, info.origin_m)}`;
    $('timings').textContent = JSON.stringify({ ...timings, bytes: state.api.bytes, points: state.pointsReceived,
                                                point_bytes: state.api.pointBytes, wire_point_bytes: wirePointBytes(),
                                                patches: state.patches, cnn_patches: state.cnnPatches,
                                                detail_patches: state.detailPatches,
                                                retries: state.retries, empty_patch_batches: state.emptyBatches,
                                                full_res_points: state.lodPoints,
                                                levels_dropped: state.levelsDropped,
                                                errors: state.errors, last_error: state.lastError });
    if ('terrain' in timings && 'overview' in timings && !state.complete) {
      state.complete = true;
      document.title = 'lidarscout · complete';
    }
    if ('idle' in timings && !state.clicked) {
      state.clicked = true;
      scriptedClicks();
    }
  }
  requestAnimationFrame(frame);
}

const COLOUR_MODES = ['rgb', 'elevation', 'intensity', 'classification'];  // render's --colour names

async function main() {
  performance.setResourceTimingBufferSize(100000);
  if (COLOUR_MODES.includes(hash.get('colour'))) {  // #colour=elevation, as render's --colour
    state.mode = COLOUR_MODES.indexOf(hash.get('colour'));
    $('colour').value = String(state.mode);
  }
  if (hash.get('ui') === '0') document.body.classList.add('bare');
  resize();
  const [info, palette] = await Promise.all([state.api.info(), state.api.palette()]);
  mark('info');
  state.info = info.datasets[0];
  const b = state.info.bounds_m, o = state.info.origin_m;
  state.box = [b[0] - o[0], b[1] - o[1], b[2], b[3] - o[0], b[4] - o[1], b[5]];
  state.classesSeen = new Set();
  state.renderer = new Renderer($('view'), palette);
  const canvas = $('view');
  setCamera(await initialCamera(canvas.width, canvas.height), false);
  bindInput(canvas);
  requestAnimationFrame(frame);
  state.api.tiles().then((t) => { state.tiles = t; fillTiles(t); pump(); }).catch(fail);
  await pollCells();
}

main().catch((e) => { $('progress').textContent = `error: ${e.message}`; console.error(e); });
