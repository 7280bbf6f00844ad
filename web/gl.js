// WebGL2 drawing of what the API sends: chunk points (squares of a fixed size, as render draws
// them) and heightmap patches (meshes, Lambert-shaded with render's sun and ambient; their vertical
// skirts as level ground), coloured by RGB, elevation (render's ramp), intensity (grey over the
// survey's range) or classification (render's class colours), with a class filter. Positions are
// metres from the survey's grid origin, taken relative to the camera before the matrix (as render
// subtracts it in double). The chunk points of every cell share one set of buffers, drawn in one
// call (a draw per cell cost software WebGL seconds a frame with thousands of cells); a cell that
// shows a heightmap, or was sent again, is hidden by its slot's flag.
// A point set's attributes: shader input, array of the set, components, GL type, normalised.
const POINT_ATTRIBUTES = [
  ['a_pos', 'pos', 3, 'FLOAT', false], ['a_rgb', 'rgb', 3, 'UNSIGNED_BYTE', true],
  ['a_cls', 'cls', 1, 'UNSIGNED_BYTE', false], ['a_int', 'intensity', 1, 'UNSIGNED_SHORT', false],
];
// CellPoints': the same, and each point's cell slot.
const CELL_ATTRIBUTES = [...POINT_ATTRIBUTES, ['a_slot', 'slot', 1, 'FLOAT', false]];
const ARRAY_OF = { FLOAT: Float32Array, UNSIGNED_BYTE: Uint8Array, UNSIGNED_SHORT: Uint16Array };
const SLOTS_WIDE = 4096;  // the hidden-cell flags: a texture this wide, a row per SLOTS_WIDE cells
// render's elevation ramp over the survey's height range (GLSL, shared by both programs)
const RAMP = 'texture(u_ramp, vec2(clamp((a_pos.z - u_zrange.x) / (u_zrange.y - u_zrange.x), 0.0, 1.0), 0.5)).rgb';
const POINT_VS = `#version 300 es
uniform mat4 u_vp; uniform vec3 u_cam; uniform float u_size; uniform float u_spacing; uniform float u_focal;
uniform int u_mode; uniform vec2 u_zrange; uniform vec2 u_irange;
uniform sampler2D u_ramp, u_classes, u_visible, u_hidden; uniform float u_uncoloured; uniform int u_cells;
in vec3 a_pos; in vec3 a_rgb; in float a_cls; in float a_int; in float a_slot;
out vec3 v_col;
void main() {
  bool hidden = u_cells == 1 &&
                texelFetch(u_hidden, ivec2(int(a_slot) % ${SLOTS_WIDE}, int(a_slot) / ${SLOTS_WIDE}), 0).r > 0.5;
  if (hidden || texelFetch(u_visible, ivec2(int(a_cls), 0), 0).r < 0.5) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  gl_Position = u_vp * vec4(a_pos - u_cam, 1.0);
  // full-resolution points as wide as their spacing on screen (1 to 16 px), as render's adaptive size
  gl_PointSize = u_spacing > 0.0 ? clamp(u_spacing * u_focal / max(gl_Position.w, 1e-3), 1.0, 16.0) : u_size;
  if (u_mode == 0) v_col = u_uncoloured > 0.0 ? vec3(u_uncoloured) : a_rgb;
  else if (u_mode == 1) v_col = ${RAMP};
  else if (u_mode == 2) v_col = vec3(clamp((a_int - u_irange.x) / max(1.0, u_irange.y - u_irange.x), 0.0, 1.0));
  else v_col = texelFetch(u_classes, ivec2(int(a_cls), 0), 0).rgb;
}`;
const POINT_FS = `#version 300 es
precision mediump float; in vec3 v_col; out vec4 o;
void main() { o = vec4(v_col, 1.0); }`;
// The patches' colour: their texture in RGB mode, the ramp in elevation mode, and in intensity and
// classification modes render's grey for an untextured patch (the terrain's RGB showing between the
// points of a level of detail would tint them: render, drawing every point, hides its surface).
const MESH_VS = `#version 300 es
uniform mat4 u_vp; uniform vec3 u_cam; uniform int u_mode; uniform vec2 u_zrange; uniform sampler2D u_ramp;
uniform float u_untextured;
in vec3 a_pos; in vec3 a_rgb;
out vec3 v_col; out vec3 v_rel;
void main() {
  v_rel = a_pos - u_cam;
  gl_Position = u_vp * vec4(v_rel, 1.0);
  v_col = u_mode == 1 ? ${RAMP} : u_mode >= 2 ? vec3(u_untextured) : a_rgb;
}`;
const MESH_FS = `#version 300 es
precision highp float; in vec3 v_col; in vec3 v_rel; out vec4 o;
const vec3 SUN = normalize(vec3(-0.5, 0.5, 0.7071)); const float AMBIENT = 0.35;
void main() {
  vec3 n = normalize(cross(dFdx(v_rel), dFdy(v_rel)));
  if (n.z < 0.0) n = -n;
  float level = AMBIENT + (1.0 - AMBIENT) * SUN.z;
  float shade = (AMBIENT + (1.0 - AMBIENT) * max(0.0, dot(n, SUN))) / level;
  if (n.z < 0.05) shade = 1.0;  // a skirt (vertical; no terrain texel is that steep): as level ground
  o = vec4(min(v_col * shade, vec3(1.0)), 1.0);
}`;

function compile(gl, vs, fs) {
  const p = gl.createProgram();
  for (const [type, src] of [[gl.VERTEX_SHADER, vs], [gl.FRAGMENT_SHADER, fs]]) {
    const s = gl.createShader(type);
    gl.shaderSource(s, src);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    gl.attachShader(p, s);
  }
  gl.linkProgram(p);
  if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
  return p;
}

function table(gl, rgb24) {  // 256 x 1 RGB texture from 0xBBGGRR values
  const data = new Uint8Array(256 * 4);
  rgb24.forEach((c, i) => data.set([c & 255, (c >> 8) & 255, (c >> 16) & 255, 255], 4 * i));
  const t = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, t);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA8, 256, 1, 0, gl.RGBA, gl.UNSIGNED_BYTE, data);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
  return t;
}

export class Renderer {
  constructor(canvas, palette) {
    const gl = canvas.getContext('webgl2', { antialias: false, preserveDrawingBuffer: true });
    if (!gl) throw new Error('this browser has no WebGL2');
    this.gl = gl;
    this.points = compile(gl, POINT_VS, POINT_FS);
    this.mesh = compile(gl, MESH_VS, MESH_FS);
    this.ramp = table(gl, palette.elevation);
    this.classes = table(gl, palette.classes);
    this.visible = table(gl, new Array(256).fill(0xffffff));
    this.cells = new Map();    // "ix,iy" -> {slot, data}: its points in this.cellPoints
    this.cellPoints = new CellPoints(gl, this.points);
    this.patches = new Map();  // "ix,iy" -> {vao, count}
    this.levels = [];          // full-resolution points: {vao, bufs, n, spacing}
  }

  setVisibleClasses(visible) {  // visible[c] for c in 0..255
    this.gl.deleteTexture(this.visible);
    this.visible = table(this.gl, visible.map((v) => (v ? 0xffffff : 0)));
  }

  buffer(vao, loc, data, size, type, normalised) {
    const gl = this.gl, b = gl.createBuffer();
    gl.bindVertexArray(vao);
    gl.bindBuffer(gl.ARRAY_BUFFER, b);
    gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
    gl.enableVertexAttribArray(loc);
    gl.vertexAttribPointer(loc, size, type, normalised, 0, 0);
    return b;
  }

  // Attribute buffers of a point set (POINT_ATTRIBUTES).
  pointVao(c) {
    const gl = this.gl, p = this.points, vao = gl.createVertexArray();
    const bufs = POINT_ATTRIBUTES.map(([input, array, size, type, normalised]) =>
      this.buffer(vao, gl.getAttribLocation(p, input), c[array], size, gl[type], normalised));
    gl.bindVertexArray(null);
    return { vao, bufs, n: c.n };
  }

  addCell(c) {
    const key = `${c.ix},${c.iy}`;
    this.removeCell(key);
    const slot = this.cellPoints.add(c);
    if (this.patches.has(key)) this.cellPoints.hide(slot);
    this.cells.set(key, { slot, data: c });  // (data: for picking)
  }

  clearLevels() {
    for (const l of this.levels) {
      l.bufs.forEach((b) => this.gl.deleteBuffer(b));
      this.gl.deleteVertexArray(l.vao);
    }
    this.levels = [];
  }

  // A tile's level of detail: its blocks in one set of buffers.
  addLevel(level) {
    const n = level.blocks.reduce((a, b) => a + b.n, 0);
    if (!n) return;
    const all = { n, pos: new Float32Array(3 * n), rgb: new Uint8Array(3 * n), cls: new Uint8Array(n),
                  intensity: new Uint16Array(n) };
    let o = 0;
    for (const b of level.blocks) {
      all.pos.set(b.pos, 3 * o), all.rgb.set(b.rgb, 3 * o), all.cls.set(b.cls, o), all.intensity.set(b.intensity, o);
      o += b.n;
    }
    this.levels.push({ ...this.pointVao(all), spacing: level.spacing, data: all });
  }

  removeCell(key) {
    const c = this.cells.get(key);
    if (!c) return;
    this.cellPoints.hide(c.slot);  // its points stay in the buffers, never drawn
    this.cells.delete(key);
  }

  addPatch(h) {
    const gl = this.gl, m = this.mesh, vao = gl.createVertexArray();
    const bufs = [this.buffer(vao, gl.getAttribLocation(m, 'a_pos'), h.pos, 3, gl.FLOAT, false),
                  this.buffer(vao, gl.getAttribLocation(m, 'a_rgb'), h.rgb, 3, gl.UNSIGNED_BYTE, true)];
    const ib = gl.createBuffer();
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ib);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, h.index, gl.STATIC_DRAW);
    bufs.push(ib);
    gl.bindVertexArray(null);
    const key = `${h.ix},${h.iy}`, old = this.patches.get(key);
    if (this.cells.has(key)) this.cellPoints.hide(this.cells.get(key).slot);  // as render: the heightmap instead
    if (old) {  // the network's heightmap replaces the linear one
      old.bufs.forEach((b) => gl.deleteBuffer(b));
      gl.deleteVertexArray(old.vao);
    }
    this.patches.set(key, { vao, bufs, count: h.index.length });
  }

  // The point sets drawn now, each {pos, cls, intensity, n} (what a pick searches).
  *drawnSets() {
    for (const [key, c] of this.cells) if (!this.patches.has(key)) yield c.data;
    for (const l of this.levels) yield l.data;
  }

  draw(view) {
    const gl = this.gl, [w, h] = [gl.canvas.width, gl.canvas.height];
    gl.viewport(0, 0, w, h);
    gl.clearColor(24 / 255, 26 / 255, 32 / 255, 1);  // render's background
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    const common = (p) => {
      gl.useProgram(p);
      gl.uniformMatrix4fv(gl.getUniformLocation(p, 'u_vp'), false, view.vp);
      gl.uniform3f(gl.getUniformLocation(p, 'u_cam'), view.cam.x, view.cam.y, view.cam.z);
      gl.uniform1i(gl.getUniformLocation(p, 'u_mode'), view.mode);
      gl.uniform2f(gl.getUniformLocation(p, 'u_zrange'), view.zrange[0], view.zrange[1]);
      gl.activeTexture(gl.TEXTURE0); gl.bindTexture(gl.TEXTURE_2D, this.ramp);
      gl.uniform1i(gl.getUniformLocation(p, 'u_ramp'), 0);
    };
    common(this.mesh);
    gl.uniform1f(gl.getUniformLocation(this.mesh, 'u_untextured'), view.untextured);
    gl.enable(gl.POLYGON_OFFSET_FILL);
    gl.polygonOffset(1, 1);  // points on the surface win, as render's depth bias
    for (const m of this.patches.values()) {
      gl.bindVertexArray(m.vao);
      gl.drawElements(gl.TRIANGLES, m.count, gl.UNSIGNED_INT, 0);
    }
    gl.disable(gl.POLYGON_OFFSET_FILL);
    const p = this.points;
    common(p);
    gl.uniform1f(gl.getUniformLocation(p, 'u_size'), view.pointSize);
    gl.uniform2f(gl.getUniformLocation(p, 'u_irange'), view.irange[0], view.irange[1]);
    gl.uniform1f(gl.getUniformLocation(p, 'u_uncoloured'), view.uncoloured);
    gl.activeTexture(gl.TEXTURE1); gl.bindTexture(gl.TEXTURE_2D, this.classes);
    gl.uniform1i(gl.getUniformLocation(p, 'u_classes'), 1);
    gl.activeTexture(gl.TEXTURE2); gl.bindTexture(gl.TEXTURE_2D, this.visible);
    gl.uniform1i(gl.getUniformLocation(p, 'u_visible'), 2);
    gl.uniform1f(gl.getUniformLocation(p, 'u_focal'), view.focal);
    gl.uniform1f(gl.getUniformLocation(p, 'u_spacing'), 0);
    let drawn = 0;
    for (const [key, c] of this.cells) if (!this.patches.has(key)) drawn += c.data.n;
    gl.activeTexture(gl.TEXTURE3); gl.bindTexture(gl.TEXTURE_2D, this.cellPoints.flags());
    gl.uniform1i(gl.getUniformLocation(p, 'u_hidden'), 3);
    gl.uniform1i(gl.getUniformLocation(p, 'u_cells'), 1);
    this.cellPoints.draw();
    gl.uniform1i(gl.getUniformLocation(p, 'u_cells'), 0);
    for (const l of this.levels) {
      gl.uniform1f(gl.getUniformLocation(p, 'u_spacing'), l.spacing);
      gl.bindVertexArray(l.vao);
      gl.drawArrays(gl.POINTS, 0, l.n);
      drawn += l.n;
    }
    gl.bindVertexArray(null);
    return drawn;
  }
}

// The chunk points of every cell in one set of growing buffers (capacity doubled as cells come, the
// points kept here to be uploaded again then), each cell's points tagged with its slot; a slot's flag
// in a texture hides it (a cell that shows a heightmap, or was replaced).
class CellPoints {
  constructor(gl, program) {
    this.gl = gl;
    this.loc = CELL_ATTRIBUTES.map(([input]) => gl.getAttribLocation(program, input));
    this.n = 0, this.cap = 0, this.slots = 0;
    this.vao = gl.createVertexArray();
    this.bufs = this.loc.map(() => gl.createBuffer());
    this.hidden = new Uint8Array(SLOTS_WIDE);
    this.texture = gl.createTexture();
    this.flagsDirty = true;
  }

  // Appends a cell's points {n, pos, rgb, cls, intensity}; returns its slot.
  add(c) {
    const slot = this.slots++;
    if (slot >= this.hidden.length) {
      const more = new Uint8Array(2 * this.hidden.length);
      more.set(this.hidden);
      this.hidden = more;
    }
    this.flagsDirty = true;
    if (!c.n) return slot;
    if (this.n + c.n > this.cap) this.grow(Math.max(2 * this.cap, this.n + c.n, 65536));
    const at = this.n, gl = this.gl, cell = { ...c, slot: new Float32Array(c.n).fill(slot) };
    CELL_ATTRIBUTES.forEach(([, array, size], i) => {
      const data = cell[array];
      this.arrays[array].set(data, size * at);
      gl.bindBuffer(gl.ARRAY_BUFFER, this.bufs[i]);
      gl.bufferSubData(gl.ARRAY_BUFFER, size * at * data.BYTES_PER_ELEMENT, data);
    });
    this.n += c.n;
    return slot;
  }

  grow(cap) {
    const old = this.arrays, gl = this.gl;
    this.arrays = {}, this.cap = cap;
    gl.bindVertexArray(this.vao);
    CELL_ATTRIBUTES.forEach(([, array, size, type, normalised], i) => {
      const data = this.arrays[array] = new ARRAY_OF[type](size * cap);
      if (old) data.set(old[array].subarray(0, size * this.n));
      gl.bindBuffer(gl.ARRAY_BUFFER, this.bufs[i]);
      gl.bufferData(gl.ARRAY_BUFFER, data, gl.DYNAMIC_DRAW);
      gl.enableVertexAttribArray(this.loc[i]);
      gl.vertexAttribPointer(this.loc[i], size, gl[type], normalised, 0, 0);
    });
    gl.bindVertexArray(null);
  }

  hide(slot) {
    if (this.hidden[slot]) return;
    this.hidden[slot] = 1;
    this.flagsDirty = true;
  }

  // The flags' texture (uploaded again when a flag or the slot count changed).
  flags() {
    const gl = this.gl;
    gl.bindTexture(gl.TEXTURE_2D, this.texture);
    if (this.flagsDirty) {
      const rows = Math.max(1, Math.ceil(this.hidden.length / SLOTS_WIDE));
      gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
      gl.texImage2D(gl.TEXTURE_2D, 0, gl.R8, SLOTS_WIDE, rows, 0, gl.RED, gl.UNSIGNED_BYTE,
                    this.hidden.subarray(0, rows * SLOTS_WIDE));
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
      this.flagsDirty = false;
    }
    return this.texture;
  }

  draw() {
    if (!this.n) return;
    const gl = this.gl;
    gl.bindVertexArray(this.vao);
    gl.drawArrays(gl.POINTS, 0, this.n);
  }
}
