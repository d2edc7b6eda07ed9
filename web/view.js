// The mesh view: WebGL 2, one draw call for all cells (each triangle's three vertices carry
// its colour value and barycentric coordinates, so the fragment shader draws the edges
// without a second pass), lines per boundary tag, pan and zoom by a 2x2 transform only:
// nothing is rebuilt when the view moves.
//
// A large mesh (more than `cacheAbove` GPU triangles) is drawn into a texture that covers the
// canvas and a margin around it; while the view moves, each frame is that picture moved and
// scaled (one textured quad, whatever the mesh's size), and the cells are drawn again once the
// view has stood still for `quietMs`. A GPU draws 10^6 triangles in milliseconds, but software
// WebGL or a weak laptop GPU takes up to seconds: the picture keeps panning and zooming smooth.

const CELL_VS = `#version 300 es
in vec2 a_pos;
in float a_value;
in vec3 a_bary;
uniform vec2 u_scale;
uniform vec2 u_offset;
out float v_value;
out vec3 v_bary;
void main() {
  gl_Position = vec4(a_pos * u_scale + u_offset, 0.0, 1.0);
  v_value = a_value;
  v_bary = a_bary;
}`;

// u_mode 0: plain; 1: sequential ramp (quality: red poor, blue good); 2: diverging (size
// ratio: blue too small, pale right, red too large).
const CELL_FS = `#version 300 es
precision highp float;
in float v_value;
in vec3 v_bary;
uniform int u_mode;
uniform float u_edges;
out vec4 colour;
vec3 sequential(float t) {
  t = clamp(t, 0.0, 1.0);
  vec3 a = vec3(0.84, 0.19, 0.15), b = vec3(0.99, 0.75, 0.33), c = vec3(0.57, 0.81, 0.55), d = vec3(0.17, 0.42, 0.69);
  return t < 0.33 ? mix(a, b, t / 0.33) : t < 0.66 ? mix(b, c, (t - 0.33) / 0.33) : mix(c, d, (t - 0.66) / 0.34);
}
vec3 diverging(float t) {
  t = clamp(t, -1.0, 1.0);
  vec3 lo = vec3(0.13, 0.4, 0.67), mid = vec3(0.97, 0.97, 0.95), hi = vec3(0.7, 0.09, 0.17);
  return t < 0.0 ? mix(mid, lo, -t) : mix(mid, hi, t);
}
void main() {
  vec3 c = u_mode == 0 ? vec3(0.86, 0.89, 0.93) : u_mode == 1 ? sequential(v_value) : diverging(v_value);
  // Edges: dark where a barycentric coordinate is near 0, fading out when cells are a few
  // pixels across (they would only darken the picture).
  vec3 w = fwidth(v_bary);
  vec3 near = smoothstep(vec3(0.0), w * 1.5, v_bary);
  float edge = 1.0 - min(min(near.x, near.y), near.z);
  float tiny = smoothstep(0.15, 0.45, max(max(w.x, w.y), w.z));
  edge *= u_edges * (1.0 - tiny);
  colour = vec4(mix(c, c * 0.35, edge), 1.0);
}`;

const LINE_VS = `#version 300 es
in vec2 a_pos;
uniform vec2 u_scale;
uniform vec2 u_offset;
void main() { gl_Position = vec4(a_pos * u_scale + u_offset, 0.0, 1.0); }`;

const LINE_FS = `#version 300 es
precision highp float;
uniform vec3 u_colour;
out vec4 colour;
void main() { colour = vec4(u_colour, 1.0); }`;

// Tag colours: distinct on white and on the cell colours, in order of first appearance.
export const TAG_COLOURS = [
  [0.0, 0.0, 0.0], [0.9, 0.38, 0.0], [0.0, 0.45, 0.7], [0.8, 0.0, 0.6], [0.0, 0.6, 0.3],
  [0.55, 0.35, 0.0], [0.45, 0.2, 0.8], [0.95, 0.7, 0.0], [0.3, 0.3, 0.3], [0.0, 0.7, 0.8],
];

// The cached picture, drawn as one quad: u_rect is its corners in clip coordinates.
const PICTURE_VS = `#version 300 es
uniform vec4 u_rect;
out vec2 v_uv;
void main() {
  vec2 corner = vec2(gl_VertexID & 1, gl_VertexID >> 1);
  v_uv = corner;
  gl_Position = vec4(mix(u_rect.xy, u_rect.zw, corner), 0.0, 1.0);
}`;

const PICTURE_FS = `#version 300 es
precision highp float;
in vec2 v_uv;
uniform sampler2D u_picture;
out vec4 colour;
void main() { colour = texture(u_picture, v_uv); }`;

const BACKGROUND = [1, 1, 1];

// The cached picture spans this many times the canvas in each direction (a quarter of it as a
// margin on each side, shown while panning before the cells are drawn again).
const PICTURE_SPAN = 1.5;

function compile(gl, vs, fs) {
  const prog = gl.createProgram();
  for (const [type, src] of [[gl.VERTEX_SHADER, vs], [gl.FRAGMENT_SHADER, fs]]) {
    const sh = gl.createShader(type);
    gl.shaderSource(sh, src);
    gl.compileShader(sh);
    if (!gl.getShaderParameter(sh, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(sh));
    gl.attachShader(prog, sh);
  }
  gl.linkProgram(prog);
  if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
  return prog;
}

// Geometry of one cell (3 or 4 corners as [x, y] pairs).
export function angles(corners) {
  const n = corners.length;
  const out = [];
  for (let k = 0; k < n; k++) {
    const [px, py] = corners[(k + n - 1) % n], [cx, cy] = corners[k], [nx, ny] = corners[(k + 1) % n];
    const ax = px - cx, ay = py - cy, bx = nx - cx, by = ny - cy;
    out.push(Math.atan2(Math.abs(ax * by - ay * bx), ax * bx + ay * by) * 180 / Math.PI);
  }
  return out;
}

// Radius ratio 2 r_in / r_circ of a triangle (1 for an equilateral one), as the metrics.
export function radiusRatio(a, b, c) {
  const la = Math.hypot(b[0] - c[0], b[1] - c[1]), lb = Math.hypot(a[0] - c[0], a[1] - c[1]), lc = Math.hypot(a[0] - b[0], a[1] - b[1]);
  const s = (la + lb + lc) / 2;
  const area2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
  if (area2 <= 0) return 0;
  const area = area2 / 2;
  const rin = area / s, rcirc = la * lb * lc / (4 * area);
  return 2 * rin / rcirc;
}

// Smallest scaled Jacobian at the corners of a quad (1 for a rectangle).
export function scaledJacobian(q) {
  let worst = 1;
  for (let k = 0; k < 4; k++) {
    const [px, py] = q[(k + 3) % 4], [cx, cy] = q[k], [nx, ny] = q[(k + 1) % 4];
    const ax = nx - cx, ay = ny - cy, bx = px - cx, by = py - cy;
    worst = Math.min(worst, (ax * by - ay * bx) / (Math.hypot(ax, ay) * Math.hypot(bx, by)));
  }
  return worst;
}

export class MeshView {
  constructor(canvas, { onHover } = {}) {
    this.canvas = canvas;
    this.onHover = onHover || (() => {});
    const gl = canvas.getContext('webgl2', { antialias: true, preserveDrawingBuffer: true });
    if (!gl) throw new Error('this browser has no WebGL 2');
    this.gl = gl;
    this.cellProg = compile(gl, CELL_VS, CELL_FS);
    this.lineProg = compile(gl, LINE_VS, LINE_FS);
    this.pictureProg = compile(gl, PICTURE_VS, PICTURE_FS);
    this.cacheAbove = 300000;  // GPU triangles
    this.quietMs = 150;
    this.cache = { valid: false, texture: null, fbo: null };
    this.stats = { drawn: 0, moved: 0 };  // cells drawn; frames moved from the cached picture
    this.mode = 'quality';
    this.edges = true;
    this.mesh = null;
    this.view = { cx: 0, cy: 0, scale: 1 };  // world centre and pixels per world unit
    this.hovered = -1;
    this.highlight = gl.createBuffer();  // the hovered cell's outline
    this.installInput();
    new ResizeObserver(() => this.draw()).observe(canvas);
  }

  // --- data -------------------------------------------------------------------------------

  // mesh: the page's form of a mesh (meshdata.js: flat typed arrays).
  setMesh(mesh) {
    const gl = this.gl;
    const P = mesh.points, T = mesh.triangles, Q = mesh.quads;
    // The origin of the GPU's coordinates: the bounding box's centre (float32 keeps digits).
    let x0 = Infinity, y0 = Infinity, x1 = -Infinity, y1 = -Infinity;
    for (let i = 0; i < P.length; i += 2) {
      const x = P[i], y = P[i + 1];
      if (x < x0) x0 = x; if (x > x1) x1 = x;
      if (y < y0) y0 = y; if (y > y1) y1 = y;
    }
    this.bbox = [x0, y0, x1, y1];
    this.origin = [(x0 + x1) / 2, (y0 + y1) / 2];
    const [ox, oy] = this.origin;
    // Cells as GPU triangles: a quad is two, with the diagonal hidden from the edge drawing.
    // Their corners (point indices) stay for picking.
    const nGpu = mesh.nTriangles + 2 * mesh.nQuads;
    const pos = new Float32Array(nGpu * 6), bary = new Uint8Array(nGpu * 12);
    this.corners = new Uint32Array(nGpu * 3);
    this.cellOf = new Int32Array(nGpu);  // GPU triangle -> cell (quads after triangles)
    let g = 0;
    const put = (a, b, c, cell, hide) => {
      const C = this.corners;
      C[3 * g] = a; C[3 * g + 1] = b; C[3 * g + 2] = c;
      for (let k = 0; k < 3; k++) {
        const v = C[3 * g + k];
        pos[g * 6 + 2 * k] = P[2 * v] - ox;
        pos[g * 6 + 2 * k + 1] = P[2 * v + 1] - oy;
        for (let j = 0; j < 3; j++) bary[g * 12 + 4 * k + j] = j === k || j === hide ? 255 : 0;
      }
      this.cellOf[g++] = cell;
    };
    for (let i = 0; i < mesh.nTriangles; i++) put(T[3 * i], T[3 * i + 1], T[3 * i + 2], i, -1);
    // A quad [a,b,c,d] as (a,b,c) and (a,c,d); the shared diagonal a-c is opposite b in the
    // first and d in the second, so those coordinates stay at 1 and the diagonal is not drawn.
    for (let i = 0; i < mesh.nQuads; i++) {
      const a = Q[4 * i], b = Q[4 * i + 1], c = Q[4 * i + 2], d = Q[4 * i + 3];
      put(a, b, c, mesh.nTriangles + i, 1);
      put(a, c, d, mesh.nTriangles + i, 2);
    }
    this.gpuCount = nGpu;
    this.mesh = mesh;
    this.grid = null;
    this.hovered = -1;
    this.cache.valid = false;
    this.values = this.cellValues();
    this.upload(pos, bary);
    // Boundary lines per tag.
    this.tags = [];
    const lines = [];
    for (const { tag, edges } of mesh.boundaries) {
      const arr = new Float32Array(edges.length * 2);
      for (let i = 0; i < edges.length; i++) {
        arr[2 * i] = P[2 * edges[i]] - ox;
        arr[2 * i + 1] = P[2 * edges[i] + 1] - oy;
      }
      lines.push(arr);
      this.tags.push({ tag, edges: edges.length / 2, colour: TAG_COLOURS[this.tags.length % TAG_COLOURS.length] });
    }
    this.lineBuffers?.forEach((b) => gl.deleteBuffer(b));
    this.lineBuffers = lines.map((arr) => {
      const b = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.bufferData(gl.ARRAY_BUFFER, arr, gl.STATIC_DRAW);
      return b;
    });
    this.lineCounts = lines.map((a) => a.length / 2);
    this.fit();
  }

  // The corners of cell `cell` (triangles first, then quads) as point indices.
  cellCorners(cell) {
    const m = this.mesh;
    return cell < m.nTriangles ? Array.from(m.triangles.subarray(3 * cell, 3 * cell + 3))
      : Array.from(m.quads.subarray(4 * (cell - m.nTriangles), 4 * (cell - m.nTriangles) + 4));
  }

  point(v) {
    return [this.mesh.points[2 * v], this.mesh.points[2 * v + 1]];
  }

  upload(pos, bary) {
    const gl = this.gl;
    if (this.vao) gl.deleteVertexArray(this.vao);
    for (const b of this.cellBuffers || []) gl.deleteBuffer(b);
    this.vao = gl.createVertexArray();
    gl.bindVertexArray(this.vao);
    const attr = (name, data, size, type, normalized) => {
      const b = gl.createBuffer();
      gl.bindBuffer(gl.ARRAY_BUFFER, b);
      gl.bufferData(gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
      const loc = gl.getAttribLocation(this.cellProg, name);
      gl.enableVertexAttribArray(loc);
      gl.vertexAttribPointer(loc, size, type, normalized, type === gl.UNSIGNED_BYTE ? 4 : 0, 0);
      return b;
    };
    this.cellBuffers = [attr('a_pos', pos, 2, gl.FLOAT, false), attr('a_bary', bary, 3, gl.UNSIGNED_BYTE, true)];
    this.valueBuffer = gl.createBuffer();
    this.cellBuffers.push(this.valueBuffer);
    gl.bindBuffer(gl.ARRAY_BUFFER, this.valueBuffer);
    const loc = gl.getAttribLocation(this.cellProg, 'a_value');
    gl.enableVertexAttribArray(loc);
    gl.vertexAttribPointer(loc, 1, gl.FLOAT, false, 0, 0);
    gl.bindVertexArray(null);
    this.uploadValues();
  }

  // Per cell: quality (radius ratio; a quad's smallest scaled Jacobian) and the size ratio
  // (mean edge length over the mean target size of its corners), with each GPU triangle's
  // shader value for the current mode.
  cellValues() {
    const m = this.mesh, P = m.points, S = m.sizes, T = m.triangles;
    const n = m.nTriangles + m.nQuads;
    const quality = new Float32Array(n), size = new Float32Array(n);
    // Triangles without a temporary per cell (a million of them in a large mesh).
    const a = [0, 0], b = [0, 0], c = [0, 0];
    for (let i = 0; i < m.nTriangles; i++) {
      const u = T[3 * i], v = T[3 * i + 1], w = T[3 * i + 2];
      a[0] = P[2 * u]; a[1] = P[2 * u + 1]; b[0] = P[2 * v]; b[1] = P[2 * v + 1]; c[0] = P[2 * w]; c[1] = P[2 * w + 1];
      quality[i] = radiusRatio(a, b, c);
      size[i] = S ? (Math.hypot(a[0] - b[0], a[1] - b[1]) + Math.hypot(b[0] - c[0], b[1] - c[1]) + Math.hypot(c[0] - a[0], c[1] - a[1])) /
        (S[u] + S[v] + S[w]) : NaN;
    }
    for (let i = m.nTriangles; i < n; i++) {
      const vs = this.cellCorners(i), ps = vs.map((v) => this.point(v));
      quality[i] = scaledJacobian(ps);
      let len = 0, rho = 0;
      for (let k = 0; k < 4; k++) {
        len += Math.hypot(ps[k][0] - ps[(k + 1) % 4][0], ps[k][1] - ps[(k + 1) % 4][1]);
        rho += S ? S[vs[k]] : NaN;
      }
      size[i] = len / rho;
    }
    return { quality, size };
  }

  uploadValues() {
    const gl = this.gl;
    const v = new Float32Array(this.gpuCount * 3);
    const src = this.mode === 'size' ? this.values.size : this.values.quality;
    for (let g = 0; g < this.gpuCount; g++) {
      let x = src[this.cellOf[g]];
      // Quality: 0.5..1 spans the ramp (below 0.5 is all "poor"); size: log2 of the ratio,
      // -1..1 (half to twice the target).
      x = this.mode === 'size' ? Math.log2(x) : (x - 0.5) / 0.5;
      v[3 * g] = v[3 * g + 1] = v[3 * g + 2] = x;
    }
    gl.bindBuffer(gl.ARRAY_BUFFER, this.valueBuffer);
    gl.bufferData(gl.ARRAY_BUFFER, v, gl.STATIC_DRAW);
  }

  setMode(mode) {
    this.mode = mode;
    if (this.mesh) this.uploadValues();
    this.draw();
  }

  setEdges(on) {
    this.edges = on;
    this.draw();
  }

  // --- view -------------------------------------------------------------------------------

  size() {
    const r = this.canvas.getBoundingClientRect();
    return [Math.max(1, r.width), Math.max(1, r.height)];
  }

  fit() {
    if (!this.bbox) return;
    const [w, h] = this.size();
    const [x0, y0, x1, y1] = this.bbox;
    const scale = 0.94 * Math.min(w / Math.max(x1 - x0, 1e-300), h / Math.max(y1 - y0, 1e-300));
    this.view = { cx: (x0 + x1) / 2, cy: (y0 + y1) / 2, scale };
    this.draw();
  }

  // World point -> CSS pixel within the canvas, and back.
  toScreen(x, y) {
    const [w, h] = this.size();
    return [w / 2 + (x - this.view.cx) * this.view.scale, h / 2 - (y - this.view.cy) * this.view.scale];
  }
  toWorld(px, py) {
    const [w, h] = this.size();
    return [this.view.cx + (px - w / 2) / this.view.scale, this.view.cy - (py - h / 2) / this.view.scale];
  }

  zoomAt(px, py, factor) {
    const [wx, wy] = this.toWorld(px, py);
    this.view.scale *= factor;
    const [nx, ny] = this.toWorld(px, py);
    this.view.cx += wx - nx;
    this.view.cy += wy - ny;
    this.draw();
  }

  // Shows the world box [x0, y0, x1, y1] (the tests and a user's zoom to a region).
  show(x0, y0, x1, y1) {
    const [w, h] = this.size();
    this.view = { cx: (x0 + x1) / 2, cy: (y0 + y1) / 2, scale: Math.min(w / (x1 - x0), h / (y1 - y0)) };
    this.draw();
  }

  panBy(dx, dy) {
    this.view.cx -= dx / this.view.scale;
    this.view.cy += dy / this.view.scale;
    this.draw();
  }

  installInput() {
    const c = this.canvas;
    let drag = null;
    c.addEventListener('pointerdown', (e) => {
      drag = { x: e.clientX, y: e.clientY };
      c.setPointerCapture(e.pointerId);
    });
    c.addEventListener('pointerup', (e) => {
      drag = null;
      c.releasePointerCapture(e.pointerId);
    });
    c.addEventListener('pointermove', (e) => {
      const r = c.getBoundingClientRect();
      if (drag) {
        this.panBy(e.clientX - drag.x, e.clientY - drag.y);
        drag = { x: e.clientX, y: e.clientY };
      } else {
        this.hover(e.clientX - r.left, e.clientY - r.top);
      }
    });
    c.addEventListener('pointerleave', () => this.setHovered(-1));
    c.addEventListener('wheel', (e) => {
      e.preventDefault();
      const r = c.getBoundingClientRect();
      this.zoomAt(e.clientX - r.left, e.clientY - r.top, Math.exp(-e.deltaY * 0.0015));
    }, { passive: false });
    c.addEventListener('keydown', (e) => {
      const [w, h] = this.size();
      const step = 0.1 * Math.min(w, h);
      const keys = {
        ArrowLeft: () => this.panBy(step, 0), ArrowRight: () => this.panBy(-step, 0),
        ArrowUp: () => this.panBy(0, step), ArrowDown: () => this.panBy(0, -step),
        '+': () => this.zoomAt(w / 2, h / 2, 1.25), '=': () => this.zoomAt(w / 2, h / 2, 1.25),
        '-': () => this.zoomAt(w / 2, h / 2, 0.8), '0': () => this.fit(), f: () => this.fit(),
      };
      if (keys[e.key]) {
        e.preventDefault();
        keys[e.key]();
      }
    });
  }

  // --- picking ----------------------------------------------------------------------------

  // A uniform grid of about one GPU triangle per bucket, built on the first hover: the
  // triangle under the pointer in O(1) expected.
  buildGrid() {
    const n = this.gpuCount;
    const [x0, y0, x1, y1] = this.bbox;
    const w = Math.max(x1 - x0, 1e-300), h = Math.max(y1 - y0, 1e-300);
    const nx = Math.max(1, Math.min(4096, Math.round(Math.sqrt(n * w / h)))), ny = Math.max(1, Math.min(4096, Math.round(Math.sqrt(n * h / w))));
    const P = this.mesh.points, C = this.corners;
    const cl = (v, m) => Math.max(0, Math.min(m - 1, v));
    const range = (g) => {
      let a = Infinity, b = Infinity, c = -Infinity, d = -Infinity;
      for (let k = 0; k < 3; k++) {
        const x = P[2 * C[3 * g + k]], y = P[2 * C[3 * g + k] + 1];
        a = Math.min(a, x); b = Math.min(b, y); c = Math.max(c, x); d = Math.max(d, y);
      }
      return [cl(Math.floor((a - x0) / w * nx), nx), cl(Math.floor((b - y0) / h * ny), ny),
              cl(Math.floor((c - x0) / w * nx), nx), cl(Math.floor((d - y0) / h * ny), ny)];
    };
    const start = new Uint32Array(nx * ny + 1);
    for (let g = 0; g < n; g++) {
      const [i0, j0, i1, j1] = range(g);
      for (let j = j0; j <= j1; j++) for (let i = i0; i <= i1; i++) start[j * nx + i + 1]++;
    }
    for (let k = 0; k < nx * ny; k++) start[k + 1] += start[k];
    const fill = start.slice(0, nx * ny);
    const items = new Uint32Array(start[nx * ny]);
    for (let g = 0; g < n; g++) {
      const [i0, j0, i1, j1] = range(g);
      for (let j = j0; j <= j1; j++) for (let i = i0; i <= i1; i++) items[fill[j * nx + i]++] = g;
    }
    this.grid = { nx, ny, start, items };
  }

  // The cell (index: triangles first, then quads) at world point (x, y), or -1.
  cellAt(x, y) {
    if (!this.mesh) return -1;
    if (!this.grid) this.buildGrid();
    const { nx, ny, start, items } = this.grid;
    const [x0, y0, x1, y1] = this.bbox;
    const i = Math.floor((x - x0) / Math.max(x1 - x0, 1e-300) * nx), j = Math.floor((y - y0) / Math.max(y1 - y0, 1e-300) * ny);
    if (i < 0 || j < 0 || i >= nx || j >= ny) return -1;
    const P = this.mesh.points, C = this.corners;
    for (let k = start[j * nx + i]; k < start[j * nx + i + 1]; k++) {
      const g = items[k];
      let inside = true;
      for (let e = 0; e < 3 && inside; e++) {
        const a = 2 * C[3 * g + e], b = 2 * C[3 * g + (e + 1) % 3];
        const ax = P[a], ay = P[a + 1], bx = P[b], by = P[b + 1];
        inside = (bx - ax) * (y - ay) - (by - ay) * (x - ax) >= 0;
      }
      if (inside) return this.cellOf[g];
    }
    return -1;
  }

  hover(px, py) {
    const [x, y] = this.toWorld(px, py);
    this.setHovered(this.cellAt(x, y));
  }

  setHovered(cell) {
    if (cell === this.hovered) return;
    this.hovered = cell;
    this.onHover(cell < 0 ? null : this.describe(cell));
    this.draw();
  }

  // What the page shows of one cell.
  describe(cell) {
    const nt = this.mesh.nTriangles;
    const corners = this.cellCorners(cell).map((v) => this.point(v));
    return {
      cell, kind: corners.length === 3 ? 'triangle' : 'quad', index: cell < nt ? cell : cell - nt,
      corners, angles: angles(corners),
      quality: this.values.quality[cell], size: this.values.size[cell],
    };
  }

  // --- drawing ----------------------------------------------------------------------------

  draw() {
    if (this.pending) return;
    this.pending = true;
    requestAnimationFrame(() => {
      this.pending = false;
      this.drawNow();
    });
  }

  drawNow() {
    const gl = this.gl, c = this.canvas;
    const dpr = window.devicePixelRatio || 1;
    const [w, h] = this.size();
    if (c.width !== Math.round(w * dpr) || c.height !== Math.round(h * dpr)) {
      c.width = Math.round(w * dpr);
      c.height = Math.round(h * dpr);
    }
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, c.width, c.height);
    gl.clearColor(...BACKGROUND, 1);
    gl.clear(gl.COLOR_BUFFER_BIT);
    if (!this.mesh) return;
    if (this.gpuCount <= this.cacheAbove) {
      this.drawCells(this.view, w, h);
    } else {
      const k = this.cache;
      const same = k.valid && k.mode === this.mode && k.edges === this.edges && k.cssW === w && k.cssH === h;
      if (same && (k.view.cx !== this.view.cx || k.view.cy !== this.view.cy || k.view.scale !== this.view.scale)) {
        // The view moved: the picture, moved; the cells once the view stands still.
        this.stats.moved++;
        clearTimeout(this.quiet);
        this.quiet = setTimeout(() => this.refresh(), this.quietMs);
      } else if (!same) {
        this.paint(w, h);
      }
      this.drawPicture(w, h);
    }
    this.drawLines(w, h);
  }

  // Draws the cells again for the current view now (what the quiet time would do; the tests
  // call it to reach the settled picture without waiting).
  refresh() {
    clearTimeout(this.quiet);
    this.quiet = null;
    if (!this.mesh || this.gpuCount <= this.cacheAbove) return this.drawNow();
    const [w, h] = this.size();
    this.paint(w, h);
    this.drawNow();
  }

  // The cells under view `view` into the bound framebuffer (viewport set by the caller),
  // which spans w x h CSS pixels.
  drawCells(view, w, h) {
    const gl = this.gl;
    // clip = (p + origin - centre) * 2 scale / size
    const sx = 2 * view.scale / w, sy = 2 * view.scale / h;
    gl.useProgram(this.cellProg);
    gl.uniform2f(gl.getUniformLocation(this.cellProg, 'u_scale'), sx, sy);
    gl.uniform2f(gl.getUniformLocation(this.cellProg, 'u_offset'), (this.origin[0] - view.cx) * sx, (this.origin[1] - view.cy) * sy);
    gl.uniform1i(gl.getUniformLocation(this.cellProg, 'u_mode'), { plain: 0, quality: 1, size: 2 }[this.mode]);
    gl.uniform1f(gl.getUniformLocation(this.cellProg, 'u_edges'), this.edges ? 1 : 0);
    gl.bindVertexArray(this.vao);
    gl.drawArrays(gl.TRIANGLES, 0, this.gpuCount * 3);
    gl.bindVertexArray(null);
    this.stats.drawn++;
  }

  // Draws the cells into the cached picture: the canvas's pixels and a margin around them.
  paint(w, h) {
    const gl = this.gl, k = this.cache, c = this.canvas;
    const max = Math.min(gl.getParameter(gl.MAX_TEXTURE_SIZE), gl.getParameter(gl.MAX_VIEWPORT_DIMS)[0]);
    // Device pixels: the canvas's plus an even margin, so that a whole-pixel pan samples the
    // picture at its texel centres (a pan moves it, never blurs it).
    const span = (n) => Math.min(max, n + 2 * Math.round(n * (PICTURE_SPAN - 1) / 2));
    const W = span(c.width), H = span(c.height);
    if (!k.texture || k.W !== W || k.H !== H) {
      if (k.texture) gl.deleteTexture(k.texture);
      if (k.fbo) gl.deleteFramebuffer(k.fbo);
      k.texture = gl.createTexture();
      gl.bindTexture(gl.TEXTURE_2D, k.texture);
      gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA8, W, H);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
      k.fbo = gl.createFramebuffer();
      gl.bindFramebuffer(gl.FRAMEBUFFER, k.fbo);
      gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, k.texture, 0);
      k.W = W;
      k.H = H;
    }
    gl.bindFramebuffer(gl.FRAMEBUFFER, k.fbo);
    gl.viewport(0, 0, W, H);
    gl.clearColor(...BACKGROUND, 1);
    gl.clear(gl.COLOR_BUFFER_BIT);
    // The picture's extent in CSS pixels at the view's scale (its resolution may be capped).
    const pw = w * W / c.width, ph = h * H / c.height;
    this.drawCells(this.view, pw, ph);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.viewport(0, 0, c.width, c.height);
    Object.assign(k, { valid: true, view: { ...this.view }, mode: this.mode, edges: this.edges, cssW: w, cssH: h, pw, ph });
  }

  // The cached picture where its world rectangle falls in the current view.
  drawPicture(w, h) {
    const gl = this.gl, k = this.cache, v = this.view;
    const hx = k.pw / 2 / k.view.scale, hy = k.ph / 2 / k.view.scale;  // world half extents
    const clipX = (x) => (x - v.cx) * 2 * v.scale / w, clipY = (y) => (y - v.cy) * 2 * v.scale / h;
    gl.useProgram(this.pictureProg);
    gl.uniform4f(gl.getUniformLocation(this.pictureProg, 'u_rect'),
      clipX(k.view.cx - hx), clipY(k.view.cy - hy), clipX(k.view.cx + hx), clipY(k.view.cy + hy));
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, k.texture);
    gl.uniform1i(gl.getUniformLocation(this.pictureProg, 'u_picture'), 0);
    gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
  }

  // Boundary lines per tag and the hovered cell's outline, over the cells.
  drawLines(w, h) {
    const gl = this.gl;
    const sx = 2 * this.view.scale / w, sy = 2 * this.view.scale / h;
    gl.useProgram(this.lineProg);
    gl.uniform2f(gl.getUniformLocation(this.lineProg, 'u_scale'), sx, sy);
    gl.uniform2f(gl.getUniformLocation(this.lineProg, 'u_offset'), (this.origin[0] - this.view.cx) * sx, (this.origin[1] - this.view.cy) * sy);
    const loc = gl.getAttribLocation(this.lineProg, 'a_pos');
    const lines = (buffer, count, colour, mode) => {
      gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
      gl.enableVertexAttribArray(loc);
      gl.vertexAttribPointer(loc, 2, gl.FLOAT, false, 0, 0);
      gl.uniform3f(gl.getUniformLocation(this.lineProg, 'u_colour'), ...colour);
      gl.drawArrays(mode, 0, count);
    };
    this.lineBuffers.forEach((b, i) => lines(b, this.lineCounts[i], this.tags[i].colour, gl.LINES));
    if (this.hovered >= 0) {
      const d = this.describe(this.hovered);
      const arr = new Float32Array(d.corners.flatMap(([x, y]) => [x - this.origin[0], y - this.origin[1]]));
      gl.bindBuffer(gl.ARRAY_BUFFER, this.highlight);
      gl.bufferData(gl.ARRAY_BUFFER, arr, gl.DYNAMIC_DRAW);
      lines(this.highlight, d.corners.length, [1, 0, 1], gl.LINE_LOOP);
    }
    gl.disableVertexAttribArray(loc);
  }

  // The colour drawn at CSS pixel (px, py), [r, g, b] in 0..255 (for the tests).
  pixel(px, py) {
    this.drawNow();
    const gl = this.gl, dpr = this.canvas.width / this.size()[0];
    const out = new Uint8Array(4);
    gl.readPixels(Math.round(px * dpr), Math.round(this.canvas.height - 1 - py * dpr), 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, out);
    return [out[0], out[1], out[2]];
  }
}
