// The HTML controls: each one sets a parameter by its URL name; `refresh` writes the state back
// into them (after a refused value too, so they never show what is not drawn).
import { download, showMessage } from './ui.js';
import { ANIMATIONS, LABELS, NORMALS, SCHEMES, SPACINGS } from './params.js';

const $ = (id) => document.getElementById(id);

const LOD_DEFAULTS = { screen: '8', distance: '1,10,16', tolerance: '0.001' };

function splitSpec(spec) {
  const i = spec.indexOf(':');
  return i < 0 ? [spec, ''] : [spec.slice(0, i), spec.slice(i + 1)];
}

function formatBytes(n) {
  if (!Number.isFinite(n)) return '–';
  if (n < 1024) return `${n} B`;
  if (n < 1024 * 1024) return `${(n / 1024).toFixed(1)} KiB`;
  return `${(n / 1024 / 1024).toFixed(2)} MiB`;
}

/** Fills the menus of the parameters with a fixed list of names from params.js's lists. */
function fillMenus(form) {
  const lists = { scheme: SCHEMES, normals: NORMALS, spacing: SPACINGS, animate: ANIMATIONS };
  for (const [name, values] of Object.entries(lists)) {
    form.querySelector(`select[name="${name}"]`).replaceChildren(
      ...values.map((v) => {
        const o = document.createElement('option');
        o.value = v;
        o.textContent = LABELS[v] ?? v;
        return o;
      }),
    );
  }
}

export function bindControls({ state, set, load, getCore, capture }) {
  const form = $('controls');
  fillMenus(form);
  const named = [...form.querySelectorAll('[name]')];
  let tagTarget = null;

  for (const input of named) {
    input.addEventListener('change', () => {
      set({ [input.name]: input.type === 'checkbox' ? input.checked : input.value });
    });
  }
  form.addEventListener('submit', (e) => e.preventDefault());

  const setLod = () => {
    const kind = $('lod-kind').value;
    if (kind === 'fixed') return set({ lod: 'fixed' });
    if ($('lod-value').value.trim() === '') $('lod-value').value = LOD_DEFAULTS[kind];
    return set({ lod: `${kind}:${$('lod-value').value.trim()}` });
  };
  $('lod-kind').addEventListener('change', () => {
    $('lod-value').value = LOD_DEFAULTS[$('lod-kind').value] ?? '';
    setLod();
  });
  $('lod-value').addEventListener('change', setLod);

  const setDisplace = () => {
    const kind = $('displace-kind').value;
    set({ displace: kind === 'none' ? 'none' : `${kind}:${$('displace-amplitude').value},${$('displace-frequency').value}` });
  };
  for (const id of ['displace-kind', 'displace-amplitude', 'displace-frequency']) $(id).addEventListener('input', setDisplace);

  for (const box of form.querySelectorAll('[data-panel]')) {
    box.addEventListener('change', () => {
      const panels = [...form.querySelectorAll('[data-panel]')].filter((b) => b.checked).map((b) => b.dataset.panel);
      set({ panels });
    });
  }

  // A file's animation clips: the menu, play/pause, and the time slider (dragging pauses).
  $('clip').addEventListener('change', () => set({ clip: $('clip').value }));
  $('play').addEventListener('click', () => set({ playing: !state.playing }));
  $('clip-time').addEventListener('input', () => set({ time: Number($('clip-time').value), playing: false }));

  $('sample').addEventListener('change', () => {
    if ($('sample').value) load($('sample').value);
  });
  $('file').addEventListener('change', () => {
    const file = $('file').files?.[0];
    if (file) load(file);
  });

  const guarded = (fn) => async () => {
    try {
      await fn();
    } catch (e) {
      showMessage(e instanceof Error ? e.message : String(e));
    }
  };
  const base = () => (state.mesh.split('/').pop() || 'mesh').replace(/\.[^.]*$/, '');
  $('export-glb').addEventListener('click', guarded(() => download(`${base()}-${state.scheme}.glb`, getCore().exportGlb(), 'model/gltf-binary')));
  $('screenshot').addEventListener('click', guarded(async () => download(`${base()}.png`, await capture(), 'image/png')));
  $('save-tags').addEventListener('click', guarded(() => download(`${base()}-tags.json`, getCore().tagsJson(), 'application/json')));

  // Tag editing: the picked edge or vertex, and its sliders.
  const applyTag = guarded(() => {
    const viewer = window.viewer;
    if (tagTarget?.edge) viewer.setEdgeSharpness(tagTarget.edge[0], tagTarget.edge[1], Number($('sharpness').value));
    else if (tagTarget?.vertex !== undefined) viewer.setVertexTension(tagTarget.vertex, Number($('tension').value), Number($('bias').value));
  });
  for (const id of ['sharpness', 'tension', 'bias']) $(id).addEventListener('change', applyTag);

  // The stats panel, twice a second.
  setInterval(() => {
    const core = getCore();
    if (!core) return;
    let s;
    try {
      s = { ...core.stats(), fps: window.viewer?.stats ? window.viewer.stats().fps : 0 };
    } catch {
      return; // a failing device reports through the frame loop's message
    }
    const rows = [
      ['adapter', s.adapter],
      ['backend', s.backend],
      ['frame', `${Number(s.frameMs).toFixed(2)} ms, ${Number(s.fps).toFixed(0)} fps`],
      ['coarse triangles', s.coarseTriangles],
      ['refined triangles', s.refinedTriangles],
      ['uploaded last frame', formatBytes(s.uploadedBytes)],
      ['pattern GPU bytes', formatBytes(s.patternBytes)],
      ['static refined buffer', formatBytes(s.staticBytes)],
      ['level', s.level],
    ];
    if (s.clips?.length) rows.push(['clip', `${state.clip} ${Number(core.get().time).toFixed(2)} / ${Number(s.duration).toFixed(2)} s`]);
    if (s.poseError) rows.push(['pose refused', s.poseError]);
    const table = $('stats');
    table.replaceChildren(
      ...rows.map(([k, v]) => {
        const tr = document.createElement('tr');
        for (const text of [k, String(v)]) {
          const td = document.createElement('td');
          td.textContent = text;
          tr.append(td);
        }
        return tr;
      }),
    );
  }, 500);

  return {
    async fillSamples() {
      const select = $('sample');
      let names = [];
      try {
        const r = await fetch('samples/index.json');
        if (r.ok) names = await r.json();
      } catch {
        names = []; // no samples list: the menu stays empty, files and URLs still work
      }
      const first = document.createElement('option');
      first.value = '';
      first.textContent = '(choose)';
      select.replaceChildren(
        first,
        ...names.map((n) => {
          const o = document.createElement('option');
          o.value = `samples/${n}`;
          o.textContent = n;
          return o;
        }),
      );
    },

    refresh() {
      for (const input of named) {
        const v = state[input.name];
        if (input.type === 'checkbox') input.checked = Boolean(v);
        else input.value = String(v);
      }
      const [lodKind, lodValue] = splitSpec(state.lod);
      $('lod-kind').value = lodKind;
      if (lodKind !== 'fixed') $('lod-value').value = lodValue;
      const [dKind, dValue] = splitSpec(state.displace);
      $('displace-kind').value = dKind;
      if (dKind !== 'none') {
        const [a, f] = dValue.split(',');
        $('displace-amplitude').value = a;
        $('displace-frequency').value = f;
      }
      for (const box of form.querySelectorAll('[data-panel]')) box.checked = state.panels.includes(box.dataset.panel);
      this.refreshClip();
      const sample = [...$('sample').options].find((o) => o.value === state.mesh);
      $('sample').value = sample ? sample.value : '';
    },

    /** The clip controls: shown when the loaded file has clips, holding the engine's state. */
    refreshClip() {
      const core = getCore();
      let s = null;
      try {
        s = core?.stats();
      } catch {
        s = null;
      }
      const clips = s?.clips ?? [];
      $('clip-row').hidden = clips.length === 0;
      if (clips.length === 0) return;
      const names = ['none', ...clips];
      if ([...$('clip').options].map((o) => o.value).join('\n') !== names.join('\n')) {
        $('clip').replaceChildren(
          ...names.map((n) => {
            const o = document.createElement('option');
            o.value = n;
            o.textContent = n === 'none' ? '(rest pose)' : n;
            return o;
          }),
        );
      }
      // A clip given by index shows by name.
      const index = Number(state.clip);
      $('clip').value = Number.isInteger(index) && clips[index] !== undefined && !clips.includes(state.clip) ? clips[index] : state.clip;
      $('play').textContent = state.playing ? 'pause' : 'play';
      $('play').disabled = state.clip === 'none';
      $('clip-time').disabled = state.clip === 'none';
      $('clip-time').max = String(Math.max(Number(s.duration) || 0, 0.01));
      this.showTime(state.time);
    },

    /** The time slider and its label at `time` seconds. */
    showTime(time) {
      $('clip-time').value = String(time);
      $('clip-time-label').textContent = `${Number(time).toFixed(2)} s`;
    },

    editTag(target) {
      tagTarget = target;
      $('tag-edit').hidden = false;
      $('tag-target').textContent = target.edge ? `edge ${target.edge[0]}–${target.edge[1]}` : `vertex ${target.vertex}`;
      $('sharpness-row').hidden = !target.edge;
      $('tension-row').hidden = !!target.edge;
      $('bias-row').hidden = !!target.edge;
    },
  };
}
