// Where each value of a JSON text is: a map from JSON pointer (RFC 6901) to character
// offsets, so that a problem's pointer from the server can be shown at its field in the
// editor. The text is assumed to be valid JSON (the page checks with JSON.parse first).

function escapeToken(key) {
  return key.replace(/~/g, '~0').replace(/\//g, '~1');
}

// Returns Map(pointer -> {start, end, keyStart}) for every value; keyStart is the offset of
// the member's name (or of the value itself for array items and the root).
export function locate(text) {
  const places = new Map();
  let i = 0;
  const ws = () => {
    while (i < text.length && ' \t\n\r'.includes(text[i])) i++;
  };
  const string = () => {
    const start = i++;
    while (i < text.length && text[i] !== '"') i += text[i] === '\\' ? 2 : 1;
    i++;
    return JSON.parse(text.slice(start, i));
  };
  const value = (pointer, keyStart) => {
    ws();
    const start = i;
    const c = text[i];
    if (c === '{') {
      i++;
      ws();
      while (text[i] !== '}' && i < text.length) {
        ws();
        const nameAt = i;
        const name = string();
        ws();
        i++;  // ':'
        value(pointer + '/' + escapeToken(name), nameAt);
        ws();
        if (text[i] === ',') i++;
        ws();
      }
      i++;
    } else if (c === '[') {
      i++;
      ws();
      let n = 0;
      while (text[i] !== ']' && i < text.length) {
        value(pointer + '/' + n++, null);
        ws();
        if (text[i] === ',') i++;
        ws();
      }
      i++;
    } else if (c === '"') {
      string();
    } else {
      while (i < text.length && !',}] \t\n\r'.includes(text[i])) i++;
    }
    places.set(pointer, { start, end: i, keyStart: keyStart ?? start });
  };
  value('', null);
  return places;
}

// The place of `pointer` in `text`, or of its nearest ancestor that exists (a problem about a
// missing member points into its parent), with the pointer actually found.
export function place(text, pointer) {
  const places = locate(text);
  let p = pointer || '';
  for (;;) {
    if (places.has(p)) return { pointer: p, ...places.get(p) };
    if (p === '') return null;
    p = p.slice(0, p.lastIndexOf('/'));
  }
}

// 0-based line of a character offset.
export function lineOf(text, offset) {
  let line = 0;
  for (let k = 0; k < offset && k < text.length; k++) if (text.charCodeAt(k) === 10) line++;
  return line;
}
