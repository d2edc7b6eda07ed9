// The page's form of a mesh: flat typed arrays, read either from the API's JSON answer (small
// meshes, with their metrics) or from its binary legacy VTK (large ones: numbers as bytes, no
// text to parse and nothing for the server to compress).
//
//   { nPoints, points: Float64Array [x0, y0, x1, y1, ...],
//     nTriangles, triangles: Uint32Array [a, b, c, ...] (corners; a 6-node triangle's first 3),
//     nQuads, quads: Uint32Array [a, b, c, d, ...],
//     boundaries: [{ tag, edges: Uint32Array [a, b, ...] }, ...] (in the answer's tag order),
//     sizes: Float64Array (rho at each point) or null }

function flat(rows, width, Type) {
  const out = new Type(rows.length * width);
  for (let i = 0; i < rows.length; i++) {
    const r = rows[i];
    for (let k = 0; k < width; k++) out[i * width + k] = r[k];
  }
  return out;
}

// mesh: the "mesh" member of a format=json answer.
export function fromJson(mesh) {
  const tris = mesh.triangles || [], quads = mesh.quads || [];
  return {
    nPoints: mesh.points.length, points: flat(mesh.points, 2, Float64Array),
    nTriangles: tris.length, triangles: flat(tris, 3, Uint32Array),
    nQuads: quads.length, quads: flat(quads, 4, Uint32Array),
    boundaries: Object.entries(mesh.boundaries || {}).map(([tag, edges]) => ({ tag, edges: flat(edges, 2, Uint32Array) })),
    sizes: mesh.sizes ? Float64Array.from(mesh.sizes) : null,
  };
}

// VTK cell types the API writes: triangle, quadratic triangle, quad, line, quadratic edge.
const VTK_TRIANGLE = 5, VTK_QUADRATIC_TRIANGLE = 22, VTK_QUAD = 9, VTK_LINE = 3, VTK_QUADRATIC_EDGE = 21;

// A reader of legacy VTK files in BINARY form (big-endian numbers between text lines).
class VtkReader {
  constructor(buffer) {
    this.bytes = new Uint8Array(buffer);
    this.data = new DataView(buffer);
    this.pos = 0;
  }

  // The next non-empty text line, or null at the end.
  line() {
    const b = this.bytes;
    while (this.pos < b.length) {
      let end = this.pos;
      while (end < b.length && b[end] !== 10) end++;
      let s = '';
      for (let i = this.pos; i < end; i++) s += String.fromCharCode(b[i]);
      this.pos = end + 1;
      s = s.trim();
      if (s) return s;
    }
    return null;
  }

  numbers(count, type) {
    const width = { double: 8, float: 4, int: 4, vtktypeint32: 4, long: 8 }[type];
    if (!width) throw new Error(`VTK: numbers of type ${type} are not read here`);
    if (this.pos + count * width > this.bytes.length) throw new Error('VTK: the file ends inside its data');
    const out = type === 'double' || type === 'float' ? new Float64Array(count) : new Int32Array(count);
    const d = this.data;
    let p = this.pos;
    if (type === 'double') for (let i = 0; i < count; i++, p += 8) out[i] = d.getFloat64(p);
    else if (type === 'float') for (let i = 0; i < count; i++, p += 4) out[i] = d.getFloat32(p);
    else if (type === 'long') for (let i = 0; i < count; i++, p += 8) out[i] = Number(d.getBigInt64(p));
    else for (let i = 0; i < count; i++, p += 4) out[i] = d.getInt32(p);
    this.pos = p;
    return out;
  }
}

// The tag names the API's VTK writer puts in the title line: "meshd tags: 0=name 1=name ...".
// Names are found in index order, so a name with spaces survives; the title is cut at 255
// characters, so with many tags the last name read may be short and later ones are "tag <index>".
function tagNames(title) {
  const names = [];
  const body = title.replace(/^meshd tags:/, '');
  let at = body.indexOf(' 0=');
  while (at >= 0) {
    const k = names.length;
    const start = at + ` ${k}=`.length;
    const next = body.indexOf(` ${k + 1}=`, start);
    names.push(body.slice(start, next < 0 ? undefined : next));
    at = next;
  }
  return names;
}

// buffer: an ArrayBuffer holding a format=vtk answer.
export function fromVtk(buffer) {
  const r = new VtkReader(buffer);
  if (!/^# vtk DataFile/.test(r.line() || '')) throw new Error('VTK: not a legacy VTK file');
  const names = tagNames(r.line() || '');
  if (r.line() !== 'BINARY') throw new Error('VTK: not a BINARY file');
  let points = null, cells = null, types = null, tags = null, sizes = null, section = null;
  for (let l = r.line(); l !== null; l = r.line()) {
    const w = l.split(/\s+/);
    if (w[0] === 'DATASET') {
      if (w[1] !== 'UNSTRUCTURED_GRID') throw new Error(`VTK: a ${w[1]} dataset`);
    } else if (w[0] === 'POINTS') {
      points = r.numbers(3 * Number(w[1]), w[2]);
    } else if (w[0] === 'CELLS') {
      cells = { count: Number(w[1]), list: r.numbers(Number(w[2]), 'int') };
    } else if (w[0] === 'CELL_TYPES') {
      types = r.numbers(Number(w[1]), 'int');
    } else if (w[0] === 'CELL_DATA' || w[0] === 'POINT_DATA') {
      section = { kind: w[0], count: Number(w[1]) };
    } else if (w[0] === 'SCALARS') {
      const components = Number(w[3] || 1);
      const table = r.line();
      if (!/^LOOKUP_TABLE/.test(table || '')) throw new Error('VTK: SCALARS without a LOOKUP_TABLE line');
      const values = r.numbers(section.count * components, w[2]);
      if (section.kind === 'CELL_DATA' && w[1] === 'tag') tags = values;
      if (section.kind === 'POINT_DATA' && w[1] === 'target_size') sizes = values;
    } else {
      throw new Error(`VTK: unexpected line "${l.slice(0, 40)}"`);
    }
  }
  if (!points || !cells || !types) throw new Error('VTK: points, cells or cell types missing');
  const nPoints = points.length / 3;
  const xy = new Float64Array(2 * nPoints);
  for (let i = 0; i < nPoints; i++) {
    xy[2 * i] = points[3 * i];
    xy[2 * i + 1] = points[3 * i + 1];
  }
  // Count, then fill: triangles, quads, and edges per tag.
  let nt = 0, nq = 0;
  const perTag = new Map();
  for (let c = 0; c < types.length; c++) {
    const t = types[c];
    if (t === VTK_TRIANGLE || t === VTK_QUADRATIC_TRIANGLE) nt++;
    else if (t === VTK_QUAD) nq++;
    else if (t === VTK_LINE || t === VTK_QUADRATIC_EDGE) {
      const tag = tags ? tags[c] : 0;
      perTag.set(tag, (perTag.get(tag) || 0) + 1);
    }
  }
  const triangles = new Uint32Array(3 * nt), quads = new Uint32Array(4 * nq);
  // Every tag of the title, as the JSON has them (with or without edges), and any beyond it.
  const order = [...new Set([...names.keys(), ...perTag.keys()])].sort((a, b) => a - b);
  const edges = new Map(order.map((tag) => [tag, { fill: 0, list: new Uint32Array(2 * (perTag.get(tag) || 0)) }]));
  const L = cells.list;
  let p = 0, it = 0, iq = 0;
  for (let c = 0; c < types.length; c++) {
    const n = L[p], t = types[c];
    if (t === VTK_TRIANGLE || t === VTK_QUADRATIC_TRIANGLE) {
      triangles[it++] = L[p + 1]; triangles[it++] = L[p + 2]; triangles[it++] = L[p + 3];
    } else if (t === VTK_QUAD) {
      for (let k = 1; k <= 4; k++) quads[iq++] = L[p + k];
    } else if (t === VTK_LINE || t === VTK_QUADRATIC_EDGE) {
      const e = edges.get(tags ? tags[c] : 0);
      e.list[e.fill++] = L[p + 1];
      e.list[e.fill++] = L[p + 2];
    }
    p += n + 1;
  }
  return {
    nPoints, points: xy, nTriangles: nt, triangles, nQuads: nq, quads,
    boundaries: order.map((tag) => ({ tag: names[tag] ?? `tag ${tag}`, edges: edges.get(tag).list })),
    sizes: sizes ? Float64Array.from(sizes) : null,
  };
}
