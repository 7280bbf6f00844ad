// The API of `lidarscout serve` (src/serve/server.hpp) and its binary forms
// (src/serve/encoding.hpp) decoded into typed arrays ready for WebGL.
const NO_HEIGHT = 65535;

export class Api {
  constructor(dataset) {
    this.token = new URLSearchParams(location.search).get('token');
    this.dataset = dataset;
    this.bytes = 0;       // every body received
    this.pointBytes = 0;  // the bodies of points (chunk points and levels of detail)
  }

  url(path, params = {}) {
    const q = new URLSearchParams(params);
    if (this.token) q.set('token', this.token);
    const s = q.toString();
    return path + (s ? '?' + s : '');
  }

  async fetch(path, params, signal) {
    const res = await fetch(this.url(path, params), { signal });
    if (!res.ok) {
      const err = new Error(`${path}: HTTP ${res.status} ${(await res.text()).trim()}`);
      err.status = res.status;
      throw err;
    }
    return res;
  }

  async json(path, params, signal) {
    const text = await (await this.fetch(path, params, signal)).text();
    this.bytes += text.length;
    return JSON.parse(text);
  }

  async binary(path, params, signal) {
    const buf = await (await this.fetch(path, params, signal)).arrayBuffer();
    this.bytes += buf.byteLength;
    return buf;
  }

  d(path) { return `/api/d/${this.dataset}/${path}`; }
  info() { return this.json('/api/info'); }
  palette() { return this.json('/api/palette'); }
  tiles() { return this.json(this.d('tiles')); }
  autoCamera(w, h, fov, tile) {
    const p = { w, h, fov };
    if (tile !== undefined) p.tile = tile;
    return this.json(this.d('camera'), p);
  }

  // [{ix, iy, n}] of the cells holding chunk points so far.
  async cells() {
    const v = new DataView(await this.binary(this.d('cells')));
    const count = v.getUint32(0, true), out = [];
    for (let i = 0; i < count; ++i) {
      const o = 4 + 12 * i;
      out.push({ ix: v.getInt32(o, true), iy: v.getInt32(o + 4, true), n: v.getUint32(o + 8, true) });
    }
    return out;
  }

  static cellList(cells) { return cells.map((c) => `${c.ix},${c.iy}`).join(';'); }

  async points(cells, patchSize, attrs, signal) {
    const buf = await this.binary(this.d('points'), { cells: Api.cellList(cells), attrs }, signal);
    this.pointBytes += buf.byteLength;
    return decodePoints(buf, patchSize);
  }

  async level(tile, level, attrs, signal) {
    const buf = await this.binary(this.d(`tile/${tile}/level/${level}`), { attrs }, signal);
    this.pointBytes += buf.byteLength;
    return decodeLevel(buf);
  }

  // null while the server still loads the chunk points (503).
  // Patches with texels `step` times as large (coarsened by the server).
  async heightmaps(cells, step, method, signal, detail = false) {
    try {
      const params = { cells: Api.cellList(cells), method, step };
      if (detail) params.detail = 1;
      return decodeHeightmaps(await this.binary(this.d('heightmaps'), params, signal), 1);
    } catch (e) {
      if (e.status === 503) return null;
      throw e;
    }
  }
}

// A tile's level of detail -> {level, spacing, blocks: as decodePoints}.
export function decodeLevel(buf) {
  const v = new DataView(buf), f = (i) => v.getFloat32(4 * i, true);
  const [ox, oy, oz, blockM, spacing] = [f(0), f(1), f(2), f(3), f(4)];
  return { level: v.getUint32(20, true), spacing, blocks: decodePoints(buf, blockM, [ox, oy, oz], 32) };
}

// Point blocks (src/serve/encoding.hpp) -> [{ix, iy, n, pos: Float32Array xyz (grid frame), rgb,
// cls, intensity}] (an attribute the block does not carry: zeros); block (ix, iy) has its corner
// at origin + (ix, iy) * size.
export function decodePoints(buf, size, origin = [0, 0, 0], start = 0) {
  const v = new DataView(buf), bytes = new Uint8Array(buf), out = [];
  for (let o = start; o < buf.byteLength;) {
    const ix = v.getInt32(o, true), iy = v.getInt32(o + 4, true), n = v.getUint32(o + 8, true);
    const zMin = v.getFloat32(o + 12, true), zMax = v.getFloat32(o + 16, true);
    const attrs = bytes[o + 20], xyBits = bytes[o + 21], zBits = bytes[o + 22], posBytes = v.getUint32(o + 24, true);
    const xyStep = xyBits ? size / (2 ** xyBits - 1) : 0, zStep = zBits ? (zMax - zMin) / (2 ** zBits - 1) : 0;
    o += 28;
    const pos = new Float32Array(3 * n), x0 = origin[0] + ix * size, y0 = origin[1] + iy * size;
    const z0 = origin[2] + zMin;
    let code = 0, qz = 0, p = o;
    const varint = () => {
      let value = 0, shift = 0, b;
      do { b = bytes[p++]; value += (b & 0x7f) * 2 ** shift; shift += 7; } while (b & 0x80);
      return value;
    };
    for (let i = 0; i < n; ++i) {
      code += varint();
      const z = varint();
      qz += z & 1 ? -((z + 1) / 2) : z / 2;
      let qx = 0, qy = 0;
      for (let b = 0; b < xyBits; ++b) {
        qx |= ((code >>> (2 * b)) & 1) << b;
        qy |= ((code >>> (2 * b + 1)) & 1) << b;
      }
      pos[3 * i] = x0 + qx * xyStep, pos[3 * i + 1] = y0 + qy * xyStep, pos[3 * i + 2] = z0 + qz * zStep;
    }
    o += posBytes;
    const take = (bit, len, Type) => {
      if (!(attrs & bit)) return new Type(n);
      const a = new Type(buf.slice(o, o + len));
      o += len;
      return a;
    };
    let rgb = take(1, 3 * n, Uint8Array);
    if (attrs & 8) rgb = spread565(take(8, 2 * n, Uint16Array));
    const cls = take(2, n, Uint8Array), intensity = take(4, 2 * n, Uint16Array);
    out.push({ ix, iy, n, pos, rgb, cls, intensity });
  }
  return out;
}

// RGB 5-6-5 -> RGB triples (each channel's top bits, as the server's decoder spreads them).
function spread565(c) {
  const rgb = new Uint8Array(3 * c.length);
  for (let i = 0; i < c.length; ++i) {
    rgb[3 * i] = (c[i] >> 11) << 3, rgb[3 * i + 1] = ((c[i] >> 5) & 63) << 2, rgb[3 * i + 2] = (c[i] & 31) << 3;
  }
  return rgb;
}

// Heightmap patches -> meshes: vertices at the texel corners taken every `step` texels (height
// and colour the mean of the defined texels around a corner), a quad per block of step x step
// texels whose texels are all defined, and a skirt hanging from the patch's boundary.
export function decodeHeightmaps(buf, step) {
  const v = new DataView(buf), out = [];
  for (let o = 0; o < buf.byteLength;) {
    const ix = v.getInt32(o, true), iy = v.getInt32(o + 4, true);
    const size = v.getUint16(o + 8, true), hasColour = v.getUint16(o + 10, true) & 1;
    const ox = v.getFloat32(o + 12, true), oy = v.getFloat32(o + 16, true), texel = v.getFloat32(o + 20, true);
    const zMin = v.getFloat32(o + 24, true), zMax = v.getFloat32(o + 28, true);
    o += 32;
    const heights = new Float32Array(size * size);
    for (let i = 0; i < size * size; ++i) {
      const q = v.getUint16(o + 2 * i, true);
      heights[i] = q === NO_HEIGHT ? NaN : zMin + (q / 65534) * (zMax - zMin);
    }
    o += 2 * size * size;
    const colours = hasColour ? new Uint8Array(buf.slice(o, o + 3 * size * size)) : null;
    if (hasColour) o += 3 * size * size;
    out.push({ ix, iy, ...mesh(size, heights, colours, ox, oy, texel, Math.min(step, size)) });
  }
  return out;
}

// A corner on the patch's boundary: its height extrapolated linearly from the nearest 2 x 2
// block centres (as render's heightmap pass does), so that two patches of a seam agree up to the
// terrain's curvature; null inside the patch or where one of the four is missing.
function extrapolated(blocks, n, ci, cj) {
  if (n < 2 || (ci > 0 && ci < n && cj > 0 && cj < n)) return null;
  const i0 = Math.min(Math.max(ci - 1, 0), n - 2), j0 = Math.min(Math.max(cj - 1, 0), n - 2);
  const q = [blocks[j0 * n + i0], blocks[j0 * n + i0 + 1], blocks[(j0 + 1) * n + i0], blocks[(j0 + 1) * n + i0 + 1]];
  if (q.some((v) => !v)) return null;
  const tx = ci - (i0 + 0.5), ty = cj - (j0 + 0.5);
  const bottom = q[0][0] + tx * (q[1][0] - q[0][0]), top = q[2][0] + tx * (q[3][0] - q[2][0]);
  return bottom + ty * (top - bottom);
}

function mesh(size, heights, colours, ox, oy, texel, step) {
  const n = Math.floor(size / step), corners = n + 1;
  const block = (bi, bj) => {  // mean height and colour of a block of texels; null when any is missing
    let h = 0, r = 0, g = 0, b = 0;
    for (let j = bj * step; j < (bj + 1) * step; ++j) {
      for (let i = bi * step; i < (bi + 1) * step; ++i) {
        const k = j * size + i;
        if (Number.isNaN(heights[k])) return null;
        h += heights[k];
        if (colours) r += colours[3 * k], g += colours[3 * k + 1], b += colours[3 * k + 2];
      }
    }
    const c = step * step;
    return [h / c, r / c, g / c, b / c];
  };
  const blocks = [];
  for (let j = 0; j < n; ++j) for (let i = 0; i < n; ++i) blocks.push(block(i, j));
  const pos = new Float32Array(3 * corners * corners), rgb = new Uint8Array(3 * corners * corners);
  for (let cj = 0; cj < corners; ++cj) {
    for (let ci = 0; ci < corners; ++ci) {
      let h = 0, r = 0, g = 0, b = 0, c = 0;
      for (const [bi, bj] of [[ci - 1, cj - 1], [ci, cj - 1], [ci - 1, cj], [ci, cj]]) {
        const s = bi >= 0 && bj >= 0 && bi < n && bj < n ? blocks[bj * n + bi] : null;
        if (s) h += s[0], r += s[1], g += s[2], b += s[3], ++c;
      }
      const k = cj * corners + ci, edge = extrapolated(blocks, n, ci, cj);
      pos[3 * k] = ox + ci * step * texel, pos[3 * k + 1] = oy + cj * step * texel;
      pos[3 * k + 2] = edge ?? (c ? h / c : 0);
      const grey = colours ? 0 : 170;
      rgb[3 * k] = c && colours ? r / c : grey, rgb[3 * k + 1] = c && colours ? g / c : grey;
      rgb[3 * k + 2] = c && colours ? b / c : grey;
    }
  }
  const idx = [];
  for (let j = 0; j < n; ++j) {
    for (let i = 0; i < n; ++i) {
      if (!blocks[j * n + i]) continue;
      const a = j * corners + i;
      idx.push(a, a + 1, a + corners + 1, a, a + corners + 1, a + corners);
    }
  }
  return withSkirt(pos, rgb, idx, blocks, n, step * texel);
}

// The patch's boundary edges of its drawn blocks, each with a vertical strip hanging `depth` metres
// down (render's skirt: one quad deep), so that where two patches' extrapolated edges differ in
// height, or their blocks differ in size, the strip fills the slit between them; it lies under the
// neighbour where that is higher. Its vertices: copies of the edge's, lowered, of the same colour.
function withSkirt(pos, rgb, idx, blocks, n, depth) {
  const corners = n + 1, edges = [];
  for (let k = 0; k < n; ++k) {  // [block, corner a, corner b] along the south, north, west and east sides
    edges.push([k, k, k + 1], [(n - 1) * n + k, n * corners + k, n * corners + k + 1]);
    edges.push([k * n, k * corners, (k + 1) * corners], [k * n + n - 1, k * corners + n, (k + 1) * corners + n]);
  }
  const kept = edges.filter(([b]) => blocks[b]);
  const first = corners * corners, total = first + 2 * kept.length;
  const p = new Float32Array(3 * total), c = new Uint8Array(3 * total);
  p.set(pos), c.set(rgb);
  kept.forEach(([, a, b], e) => {
    const v = first + 2 * e;
    for (const [to, from] of [[v, a], [v + 1, b]]) {
      p.set([pos[3 * from], pos[3 * from + 1], pos[3 * from + 2] - depth], 3 * to);
      c.set(rgb.subarray(3 * from, 3 * from + 3), 3 * to);
    }
    idx.push(a, b, v + 1, a, v + 1, v);
  });
  return { pos: p, rgb: c, index: new Uint32Array(idx), triangles: idx.length / 3 };
}
