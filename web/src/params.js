// The viewer's parameters: names and meanings of the CLI's (`tessella render`), their defaults
// (the CLI's), checking, and the URL form of the whole state. Pure functions: the page, the
// fallback and the Node tests share them, before any wasm is loaded. The name lists and
// DEFAULTS are the one copy outside Rust: tessella-viewer's test
// `the_web_pages_names_and_defaults_are_these` (params.rs) holds them to the core's names and
// the engine's defaults.

export const SCHEMES = ['flat', 'phong', 'pn', 'png1', 'pn-aen', 'st', 'quadratic'];
export const SPACINGS = ['grid', 'equal', 'fractional-odd', 'fractional-even'];
export const NORMALS = ['default', 'linear', 'quadratic', 'real'];
export const ANIMATIONS = ['none', 'twist', 'bend'];

/** How the page's menus show a name of these lists, where it is not the name itself. */
export const LABELS = Object.freeze({
  phong: 'Phong',
  pn: 'PN',
  png1: 'PNG1',
  'pn-aen': 'PN-AEN',
  st: 'scalar-tagged',
  default: "the scheme's",
});

/**
 * The defaults: `tessella render`'s (crates/tessella-cli/src/args.rs, RenderArgs) but for the
 * level, 8 as the engine's (the CLI renders 16), and geomorphing on as in the engine.
 */
export const DEFAULTS = Object.freeze({
  mesh: 'samples/creature.obj',
  scheme: 'pn',
  level: 8,
  spacing: 'grid',
  lod: 'fixed',
  alpha: 0.75,
  normals: 'default',
  wireframe: false,
  displace: 'none',
  yaw: 30,
  pitch: 20,
  zoom: 1,
  pan: [0, 0],
  geomorph: true,
  animate: 'none',
  panels: [],
  tags: '',
  clip: 'none',
  time: 0,
  playing: true,
});

/** The parameters the engine's `set` takes (everything but `mesh`, which `load` takes). */
export const ENGINE_KEYS = Object.keys(DEFAULTS).filter((k) => k !== 'mesh');

function number(name, value, check = () => true, what = 'a number') {
  const x = typeof value === 'number' ? value : typeof value === 'string' && value.trim() !== '' ? Number(value) : NaN;
  if (!Number.isFinite(x) || !check(x)) throw new Error(`${name} must be ${what}, got ${JSON.stringify(String(value))}`);
  return x;
}

function oneOf(name, value, allowed) {
  const v = String(value);
  if (!allowed.includes(v)) throw new Error(`${name} must be one of ${allowed.filter(Boolean).join(', ')}, got ${JSON.stringify(v)}`);
  return v;
}

function bool(name, value) {
  if (typeof value === 'boolean') return value;
  if (value === '1' || value === 'true' || value === '') return true;
  if (value === '0' || value === 'false') return false;
  throw new Error(`${name} must be true or false, got ${JSON.stringify(String(value))}`);
}

function numbers(s) {
  return s.split(',').map((t) => (t.trim() === '' ? NaN : Number(t)));
}

/** Checks a `lod` spec as the CLI reads it: fixed, screen:PX, distance:NEAR,FAR,MAX, tolerance:D. */
export function parseLod(value) {
  const v = String(value).trim();
  if (v === 'fixed' || v === '') return 'fixed';
  const [kind, rest = ''] = v.split(/:(.*)/s);
  const xs = numbers(rest);
  const ok = xs.every((x) => Number.isFinite(x) && x > 0);
  if (kind === 'screen' && xs.length === 1 && ok) return v;
  if (kind === 'tolerance' && xs.length === 1 && ok) return v;
  if (kind === 'distance' && xs.length === 3 && ok && xs[0] < xs[1]) return v;
  throw new Error(
    `lod must be fixed, screen:PX, distance:NEAR,FAR,MAX (NEAR < FAR) or tolerance:D with positive numbers, got ${JSON.stringify(v)}`,
  );
}

/** Checks a `displace` spec as the CLI's --displace reads it: none, sine:A,F, perlin:A,F. */
export function parseDisplace(value) {
  const v = String(value).trim();
  if (v === 'none' || v === '') return 'none';
  const [kind, rest = ''] = v.split(/:(.*)/s);
  const xs = numbers(rest);
  const arity = kind === 'perlin' ? xs.length === 2 || xs.length === 3 : xs.length === 2;
  if ((kind === 'sine' || kind === 'perlin') && arity && xs.every(Number.isFinite) && xs[1] > 0) return v;
  throw new Error(
    `displace must be none, sine:AMPLITUDE,FREQUENCY or perlin:AMPLITUDE,FREQUENCY[,SEED] (finite, frequency > 0), got ${JSON.stringify(v)}`,
  );
}

const CHECKS = {
  mesh: (v) => {
    const s = String(v);
    if (s === '') throw new Error('mesh must name a file or URL');
    return s;
  },
  scheme: (v) => oneOf('scheme', v, SCHEMES),
  level: (v) => number('level', v, (x) => x >= 1 && x <= 4096, 'a number from 1 to 4096'),
  spacing: (v) => oneOf('spacing', v, SPACINGS),
  lod: parseLod,
  alpha: (v) => number('alpha', v),
  normals: (v) => oneOf('normals', v === '' || v == null ? 'default' : v, NORMALS),
  wireframe: (v) => bool('wireframe', v),
  displace: parseDisplace,
  yaw: (v) => number('yaw', v),
  pitch: (v) => number('pitch', v),
  zoom: (v) => number('zoom', v, (x) => x > 0, 'a positive number'),
  pan: (v) => {
    const xs = Array.isArray(v) ? v.map(Number) : numbers(String(v));
    if (xs.length !== 2 || !xs.every(Number.isFinite)) throw new Error(`pan must be two finite numbers x,y, got ${JSON.stringify(String(v))}`);
    return xs;
  },
  geomorph: (v) => bool('geomorph', v),
  animate: (v) => oneOf('animate', v, ANIMATIONS),
  panels: (v) => {
    const xs = Array.isArray(v) ? v.map(String) : String(v).split(',').filter((s) => s.trim() !== '');
    for (const s of xs) oneOf('panels', s.trim(), SCHEMES);
    if (xs.length > 8) throw new Error(`panels takes at most 8 schemes, got ${xs.length}`);
    return xs.map((s) => s.trim());
  },
  clip: (v) => {
    const s = String(v ?? '').trim();
    return s === '' ? 'none' : s;
  },
  time: (v) => number('time', v, (x) => x >= 0, 'a number of seconds, 0 or more'),
  playing: (v) => bool('playing', v),
  tags: (v) => {
    const s = String(v ?? '');
    if (s !== '') {
      try {
        JSON.parse(s);
      } catch (e) {
        throw new Error(`tags must be the tags JSON the CLI reads: ${e.message}`);
      }
    }
    return s;
  },
};

/**
 * Checks every entry of `params` (URL strings or typed values) and returns them typed; throws an
 * Error naming the first bad parameter (an unknown name is an error too).
 */
export function checkParams(params) {
  const out = {};
  for (const [key, value] of Object.entries(params)) {
    const check = CHECKS[key];
    if (!check) throw new Error(`unknown parameter ${JSON.stringify(key)}: the viewer takes ${Object.keys(CHECKS).join(', ')}`);
    out[key] = check(value);
  }
  return out;
}

function same(a, b) {
  return JSON.stringify(a) === JSON.stringify(b);
}

/** The URL parameters of `state`: only those that differ from the defaults, in a stable order. */
export function toSearch(state) {
  const q = new URLSearchParams();
  for (const key of Object.keys(DEFAULTS)) {
    const v = state[key];
    if (v === undefined || same(v, DEFAULTS[key])) continue;
    if (typeof v === 'boolean') q.set(key, v ? '1' : '0');
    else if (Array.isArray(v)) q.set(key, v.join(','));
    else q.set(key, String(v));
  }
  return q.toString();
}

/** The parameters a URL's query string gives (unchecked strings; `checkParams` them). */
export function fromSearch(search) {
  const q = new URLSearchParams(search);
  const out = {};
  for (const [key, value] of q) out[key] = value;
  return out;
}
