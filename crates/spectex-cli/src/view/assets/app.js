// spectex view: the page. Leaflet (CRS.Simple) shows the model as tiles the server renders;
// map point (x, y) at zoom 0 is model pixel (x, y) (Leaflet's latitude is -y). The panel is
// built from the model's JSON and the ranges the server found in the model's validation.
'use strict';
(function () {
  const $ = (id) => document.getElementById(id);
  const session = (Math.random().toString(36).slice(2) + Date.now().toString(36)).slice(0, 32);
  const opts = { filter: true, periodic: '', z: 0, seams: true };
  let state = null;
  let version = 0;
  let map = null, fine = null, coarse = null, seams = null;
  // What the browser test reads: the last redraw's times and the number of tiles loaded.
  // `anchor`: the tile grid's offset at the current zoom (see `Layer`).
  window.spectex = {
    redraws: [], tilesLoaded: 0, ready: false, view: () => viewWindow(),
    anchor: () => fine.offset(map.getZoom()),
  };
  performance.setResourceTimingBufferSize(2000);

  async function api(path, body) {
    const init = body === undefined ? {} : {
      method: 'POST', headers: { 'Content-Type': 'application/json' }, body: JSON.stringify(body),
    };
    const r = await fetch(path, init);
    const text = await r.text();
    if (!r.ok) throw new Error(text.trim());
    return text ? JSON.parse(text) : null;
  }

  // `offset`: the tile grid's (see `Layer`), in screen pixels, which are the pixels of a fine tile.
  function tileQuery(q, size, offset) {
    const p = new URLSearchParams({
      v: version, filter: opts.filter ? 1 : 0, z: opts.z, s: session, q, ox: offset.x, oy: offset.y,
    });
    if (size) p.set('size', size);
    if (opts.periodic) p.set('periodic', opts.periodic);
    return p.toString();
  }

  function windowQuery(extra) {
    const v = viewWindow();
    const p = new URLSearchParams({
      x: v.x, y: v.y, scale: v.scale, w: v.w, h: v.h, filter: opts.filter ? 1 : 0, z: opts.z, ...extra,
    });
    if (opts.periodic) p.set('periodic', opts.periodic);
    return p.toString();
  }

  // The tile grid is anchored to the view: when a redraw starts, each zoom level's grid is
  // shifted so that the view's top-left pixel is a tile corner. A grid fixed in world space
  // needs 5 × 5 tiles of 256² for an unaligned 1024² view (1.56 times its area, and the redraw's
  // time with it); anchored, 4 × 4 as at the origin. `grid` maps a zoom level to its offset: the
  // screen pixel, in [0, tile), where tile (0, 0) of that level starts. A new map for each
  // redraw; a level first shown after it is aligned with the view then (lazily), and pans keep
  // the offsets, so the tiles already loaded stay where they are. A layer keeps the map it last
  // redrew with, for its tiles never move: the fine layer keeps its old tiles, and their map,
  // until it redraws once the coarse tiles are in. Both layers redraw with the same map, so a
  // coarse tile and its fine twin share coordinates and region.
  let grid = new Map();
  const mod = (a, n) => ((a % n) + n) % n;
  const Layer = L.TileLayer.extend({
    initialize(url, options) {
      L.TileLayer.prototype.initialize.call(this, url, options);
      this._grid = grid;
    },

    redraw() {
      // The old tiles go (their `tileunload` naming their old offset) before the map changes.
      if (this._map) this._removeAllTiles();
      this._grid = grid;
      return L.TileLayer.prototype.redraw.call(this);
    },

    // The offset of zoom level `z`. A level new to the map is aligned with `topLeft`, the view's
    // top-left pixel at `z` (by default, the view's now).
    offset(z, topLeft) {
      let o = this._grid.get(z);
      if (!o) {
        const t = this.getTileSize();
        const tl = topLeft || this._map.getPixelBounds(this._map.getCenter(), z).min;
        o = L.point(mod(Math.round(tl.x), t.x), mod(Math.round(tl.y), t.y));
        this._grid.set(z, o);
      }
      return o;
    },

    // Leaflet maps tile coordinates to pixels here (`_getTiledPixelBounds` gives `_update` the
    // pixels to cover, whose tile range, keep-buffer and pruning follow; `_getTilePos` places a
    // tile; `_tileCoordsToNwSe` gives its bounds): each shifted by the level's offset, so the
    // rest of GridLayer sees a grid of whole tiles. (Retaining a parent or child level's tiles
    // while a level loads goes by coordinates alone; with levels of different offsets they are
    // kept a little less exactly, and still drawn where they belong.)
    _getTiledPixelBounds(center) {
      const map = this._map, z = this._tileZoom;
      let b = L.TileLayer.prototype._getTiledPixelBounds.call(this, center);
      // At the view's own zoom, the view's pixels exactly: Leaflet floors the centre's pixel here
      // where the map rounds the top-left corner, so with a centre half a pixel off (as zooming
      // out by the buttons leaves it) `b` began a pixel before the view, and the grid anchored
      // there left the view's last column (1024 wide) or row without a tile.
      const zoom = map._animatingZoom ? Math.max(map._animateToZoom, map.getZoom()) : map.getZoom();
      if (map.getZoomScale(zoom, z) === 1) {
        const size = map.getSize();
        const topLeft = map.project(center, z).subtract(size.divideBy(2)).round();
        b = L.bounds(topLeft, topLeft.add(size));
      }
      const o = this.offset(z, b.min);
      return L.bounds(b.min.subtract(o), b.max.subtract(o));
    },

    _getTilePos(coords) {
      return L.TileLayer.prototype._getTilePos.call(this, coords).add(this.offset(coords.z));
    },

    _tileCoordsToNwSe(coords) {
      const size = this.getTileSize();
      const nw = coords.scaleBy(size).add(this.offset(coords.z));
      return [this._map.unproject(nw, coords.z), this._map.unproject(nw.add(size), coords.z)];
    },

    getTileUrl(c) {
      const q = tileQuery(this.options.q, this.options.size, this.offset(c.z));
      return `/tile/${this._getZoomForUrl()}/${c.x}/${c.y}.png?${q}`;
    },
  });

  // The window the view shows, as `spectex render` takes it: whole screen pixels at the
  // current zoom, so its pixels are the tiles' pixels.
  function viewWindow() {
    // The model pixel at the container's top-left corner: Leaflet places tiles relative to its
    // rounded pixel origin, so this is a whole number of screen pixels.
    const topLeft = map.containerPointToLayerPoint([0, 0]).add(map.getPixelOrigin());
    const size = map.getSize();
    const scale = Math.pow(2, -map.getZoom());
    const px = Math.round(topLeft.x), py = Math.round(topLeft.y);
    return { x: px * scale, y: py * scale, scale, w: size.x, h: size.y, px, py };
  }

  function fmt(v) {
    if (Math.abs(v) >= 1e6) return v.toExponential(6).replace(/\.?0+e/, 'e').replace('e+', 'e');
    return String(Math.round(v * 1e6) / 1e6);
  }

  function showWhere() {
    const v = viewWindow();
    const c = map.getCenter();
    $('where').textContent = `centre ${fmt(c.lng)}, ${fmt(-c.lat)} · scale ${fmt(v.scale)} model px per pixel (zoom ${map.getZoom()})`;
    let cmd = `spectex render ${state.name} -o view.png --size ${v.w}x${v.h} --offset ${v.x},${v.y} --scale ${v.scale}`;
    if (!opts.filter) cmd += ' --no-filter';
    if (opts.z) cmd += ` --z ${opts.z}`;
    if (opts.periodic) cmd += ` --periodic ${opts.periodic}`;
    $('command').textContent = cmd + (state.version > 1 ? '   (with the model JSON below)' : '');
    $('dl-view').href = '/render?' + windowQuery({ download: 1 });
    $('dl-view-exr').href = '/render?' + windowQuery({
      download: 1, format: 'exr', w: Math.min(v.w, 2048), h: Math.min(v.h, 2048),
    });
    $('dl-wgsl').href = '/api/model.wgsl?z=' + opts.z;
  }

  function postView() {
    if (!map) return;
    const b = map.getPixelBounds();
    const s = Math.pow(2, -map.getZoom());
    const q = new URLSearchParams({ s: session, zoom: map.getZoom(), x0: b.min.x * s, y0: b.min.y * s, x1: b.max.x * s, y1: b.max.y * s });
    fetch('/api/view?' + q, { method: 'POST' }).catch(() => {});
  }

  function drawSeams() {
    seams.clearLayers();
    if (!opts.periodic || !opts.seams) return;
    const [pw, ph] = opts.periodic.split('x').map(Number);
    const b = map.getBounds();
    const x0 = b.getWest(), x1 = b.getEast(), y0 = -b.getNorth(), y1 = -b.getSouth();
    if ((x1 - x0) / pw + (y1 - y0) / ph > 400) return;
    const style = { color: '#ff3060', weight: 1, opacity: 0.8, interactive: false };
    for (let x = Math.ceil(x0 / pw) * pw; x <= x1; x += pw) L.polyline([[-y0, x], [-y1, x]], style).addTo(seams);
    for (let y = Math.ceil(y0 / ph) * ph; y <= y1; y += ph) L.polyline([[-y, x0], [-y, x1]], style).addTo(seams);
  }

  // Where a redraw's tile time went, from the resource timings and the server's
  // `Server-Timing` header: tiles loaded per layer and the server's milliseconds per step,
  // summed over the tiles (queue, eval, png...).
  function tileTimings() {
    const out = { coarse: 0, fine: 0, server: {} };
    for (const e of performance.getEntriesByType('resource')) {
      if (!e.name.includes('/tile/')) continue;
      out[e.name.includes('q=c') ? 'coarse' : 'fine'] += 1;
      for (const t of e.serverTiming || []) out.server[t.name] = Math.round((out.server[t.name] || 0) + t.duration);
    }
    return out;
  }

  // Coarse tiles (a quarter of the resolution, 1/16 of the work) first, then the fine ones.
  // The fine ones are asked for once the coarse ones are in: the browser sends at most six
  // requests at a time, in an order of its own, so asking for both at once lets fine tiles
  // overtake the preview. Until then the last fine tiles stay in place.
  let onCoarse = null, onFine = null;
  function redraw() {
    const t0 = performance.now();
    grid = new Map();
    const record = { coarse: null, fine: null, tiles: null };
    window.spectex.redraws.push(record);
    $('timing').textContent = 'drawing…';
    performance.clearResourceTimings();
    // A redraw replaces the one in progress, whose handlers must not fire for this one's tiles.
    if (onCoarse) coarse.off('load', onCoarse);
    if (onFine) fine.off('load', onFine);
    onCoarse = onFine = null;
    const startFine = () => {
      onFine = () => {
        onFine = null;
        record.fine = performance.now() - t0;
        record.tiles = tileTimings();
        $('timing').textContent = `redrawn in ${Math.round(record.fine)} ms (coarse ${Math.round(record.coarse ?? 0)} ms)`;
      };
      fine.once('load', onFine);
      holding = true;
      fine.redraw();
    };
    if (map.hasLayer(coarse)) {
      onCoarse = () => { onCoarse = null; record.coarse = performance.now() - t0; startFine(); };
      coarse.once('load', onCoarse);
      coarse.redraw();
    } else {
      startFine();
    }
    showWhere();
    drawSeams();
  }

  // Each frame the browser draws while tiles arrive composes the whole view, on the CPU where
  // there is no GPU: headless Chromium spent as much CPU on a redraw's two dozen frames as the
  // server spent rendering it. So during a redraw the new fine tiles are shown in batches, at
  // most one per BATCH_MS and the last ones at once; and a coarse tile whose fine twin (same
  // coordinates and grid offset) is shown is hidden rather than drawn beneath it. Pans and
  // zooms show tiles as Leaflet does.
  const BATCH_MS = 100;
  let holding = false;
  function showInBatches() {
    // (The offset too: between a redraw's start and the fine layer's redraw the two layers'
    // grids differ, and a fine tile of the same coordinates is no twin.)
    const key = (e) => {
      const c = e.coords, o = e.target.offset(c.z);
      return `${c.x}:${c.y}:${c.z}:${o.x}:${o.y}`;
    };
    const held = new Map(), shown = new Set(), coarseTiles = new Map();
    let timer = null;
    const show = (k, el) => {
      el.classList.remove('held');
      shown.add(k);
      coarseTiles.get(k)?.classList.add('covered');
    };
    const showHeld = () => {
      clearTimeout(timer);
      timer = null;
      for (const [k, el] of held) show(k, el);
      held.clear();
    };
    fine.on('tileload', (e) => {
      const k = key(e);
      if (!holding) { show(k, e.tile); return; }
      e.tile.classList.add('held');
      held.set(k, e.tile);
      if (!timer) timer = setTimeout(showHeld, BATCH_MS);
    });
    fine.on('load', () => { holding = false; showHeld(); });
    fine.on('tileunload', (e) => {
      const k = key(e);
      held.delete(k);
      shown.delete(k);
      coarseTiles.get(k)?.classList.remove('covered');
    });
    coarse.on('tileload', (e) => {
      const k = key(e);
      coarseTiles.set(k, e.tile);
      e.tile.classList.toggle('covered', shown.has(k));
    });
    coarse.on('tileunload', (e) => { coarseTiles.delete(key(e)); });
  }

  function setStatus(text) { $('status').textContent = text; }
  function showError(text) { $('error').textContent = text || ''; }

  // ---- the parameter panel -------------------------------------------------------------
  function sliderRange(desc, v) {
    let lo = desc && desc.min != null ? desc.min : -Infinity;
    let hi = desc && desc.max != null ? desc.max : Infinity;
    if (!(isFinite(lo) && isFinite(hi) && hi - lo <= 1000)) {
      const span = 2 * Math.abs(v) + 1;
      lo = Math.max(lo, v - span);
      hi = Math.min(hi, v + span);
    }
    return [lo, hi];
  }

  function numberField(label, pointer, v, desc) {
    const row = document.createElement('div');
    row.className = 'field';
    row.dataset.pointer = pointer;
    const name = document.createElement('span');
    name.textContent = label;
    name.title = `${pointer}: ${desc ? desc.range : 'no range found'}`;
    const slider = document.createElement('input');
    slider.type = 'range';
    const [lo, hi] = sliderRange(desc, v);
    const integer = desc ? desc.integer : Number.isInteger(v);
    slider.min = lo; slider.max = hi; slider.step = integer ? 1 : (hi - lo) / 1000 || 'any';
    slider.value = v;
    const shown = integer ? v : Number(v.toPrecision(7));
    slider.setAttribute('aria-label', pointer);
    const num = document.createElement('input');
    num.type = 'number';
    num.step = integer ? 1 : 'any';
    num.value = shown;
    num.title = name.title;
    const send = (x) => setField(pointer, integer ? Math.round(x) : x, row);
    slider.addEventListener('input', () => { num.value = slider.value; send(Number(slider.value)); });
    num.addEventListener('change', () => { slider.value = num.value; send(Number(num.value)); });
    row.append(name, slider, num);
    return row;
  }

  function build(container, value, pointer, label) {
    const fields = state.panel.fields || {};
    const esc = (k) => String(k).replace(/~/g, '~0').replace(/\//g, '~1');
    if (value === null) {
      const p = document.createElement('div'); p.className = 'note'; p.textContent = `${label}: none`;
      container.append(p);
    } else if (Array.isArray(value)) {
      if (value.length > 16) {
        const p = document.createElement('div'); p.className = 'note';
        p.textContent = `${label}: ${value.length} entries (in the model JSON)`;
        container.append(p);
        return;
      }
      const d = document.createElement('details');
      d.open = value.length <= 4 && value.every((x) => typeof x !== 'object');
      const s = document.createElement('summary'); s.textContent = `${label} [${value.length}]`;
      d.append(s);
      value.forEach((x, k) => build(d, x, `${pointer}/${k}`, `${label}[${k}]`));
      container.append(d);
    } else if (typeof value === 'object') {
      const f = document.createElement('fieldset');
      const lg = document.createElement('legend'); lg.textContent = label; f.append(lg);
      for (const [k, x] of Object.entries(value)) build(f, x, `${pointer}/${esc(k)}`, k);
      container.append(f);
    } else if (typeof value === 'number') {
      container.append(numberField(label, pointer, value, fields[pointer]));
    } else if (typeof value === 'boolean') {
      const l = document.createElement('label');
      const c = document.createElement('input'); c.type = 'checkbox'; c.checked = value;
      c.setAttribute('aria-label', pointer);
      c.addEventListener('change', () => setField(pointer, c.checked, l));
      l.append(c, ' ' + label);
      container.append(l);
    } else if (typeof value === 'string') {
      const row = document.createElement('div'); row.className = 'field';
      const name = document.createElement('span'); name.textContent = label;
      const desc = fields[pointer];
      let input;
      if (desc && desc.options) {
        input = document.createElement('select');
        for (const o of desc.options) {
          const opt = document.createElement('option'); opt.textContent = o; opt.selected = o === value;
          input.append(opt);
        }
      } else {
        input = document.createElement('input'); input.value = value;
      }
      input.setAttribute('aria-label', pointer);
      input.addEventListener('change', () => setField(pointer, input.value, row));
      row.append(name, input);
      container.append(row);
    }
  }

  function buildPanel() {
    const panel = $('panel');
    panel.textContent = '';
    if (state.model) {
      const [kind] = Object.keys(state.model);
      build(panel, state.model[kind], '/' + kind, kind);
    }
    $('kind').textContent = state.kind ? `· ${state.kind}` : '';
    $('z-row').hidden = !state.three_d;
  }

  // One edit in flight at a time; the latest waiting edit replaces older ones.
  let pending = null, sending = false;
  function setField(pointer, value, row) {
    if (simSet) { simSet(pointer, value, row); return; }
    pending = { pointer, value, row };
    if (!sending) flush();
  }
  async function flush() {
    if (!pending) return;
    sending = true;
    const { pointer, value, row } = pending;
    pending = null;
    try {
      const s = await api('/api/set', { pointer, value });
      row.classList.remove('bad');
      showError('');
      applyState(s, false);
    } catch (e) {
      row.classList.add('bad');
      showError(e.message);
    }
    sending = false;
    if (pending) flush();
  }

  function applyState(s, rebuild) {
    const changed = s.version !== version;
    state = s;
    version = s.version;
    if (rebuild) buildPanel();
    if (s.image) showImage(s);
    if (changed && map) redraw();
  }

  // ---- an image: exemplar, fit controls, spectra ---------------------------------------
  let fitBuilt = false;
  function showImage(s) {
    const im = s.image;
    $('image').hidden = false;
    $('exemplar').src = '/api/exemplar.png';
    $('exemplar-name').textContent = `${im.name.replace(/^'|'$/g, '').split('/').pop()} (${im.width}×${im.height})`;
    $('spectrum-exemplar').src = '/api/spectrum/exemplar.png';
    if (s.version > 0) {
      $('spectrum-synthesis').src = `/api/spectrum/synthesis.png?v=${s.version}`;
      $('synthesis').src = `/render?w=${Math.min(im.width, 4096)}&h=${Math.min(im.height, 4096)}&v=${s.version}`;
    }
    if (!fitBuilt) {
      fitBuilt = true;
      const c = $('fit-controls');
      const controls = [
        ['budget', 'J (cosines per point)', 1, 200, 1],
        ['structure', 'structure share r', 0, 1, 0.01],
        ['turbulence', 'turbulence σ (px)', 0, 32, 0.5],
      ];
      for (const [key, label, lo, hi, step] of controls) {
        const row = document.createElement('div'); row.className = 'field';
        const name = document.createElement('span'); name.textContent = label;
        const slider = document.createElement('input');
        Object.assign(slider, { type: 'range', min: lo, max: hi, step, value: im.params[key] });
        slider.setAttribute('aria-label', 'fit ' + key);
        const num = document.createElement('input');
        Object.assign(num, { type: 'number', step, value: im.params[key] });
        slider.addEventListener('input', () => { num.value = slider.value; });
        slider.addEventListener('change', () => refit({ [key]: Number(slider.value) }));
        num.addEventListener('change', () => { slider.value = num.value; refit({ [key]: Number(num.value) }); });
        row.append(name, slider, num);
        c.append(row);
      }
      const l = document.createElement('label');
      const cb = document.createElement('input'); cb.type = 'checkbox'; cb.checked = im.params.random_placement;
      cb.addEventListener('change', () => refit({ random_placement: cb.checked }));
      l.append(cb, ' random placement');
      c.append(l);
    }
    $('fit-status').textContent = im.fitting != null
      ? `fitting… ${im.fitting.toFixed(1)} s`
      : im.error ? `fit failed: ${im.error}` : im.seconds != null ? `fitted in ${im.seconds.toFixed(2)} s` : '';
  }

  async function refit(change) {
    try {
      const s = await api('/api/fit', change);
      showError('');
      applyState(s, false);
      waitForFit();
    } catch (e) { showError(e.message); }
  }

  async function waitForFit() {
    for (;;) {
      const s = await api('/api/state');
      if (s.image && s.image.fitting == null) { applyState(s, true); return s; }
      showImage(s);
      setStatus(`fitting ${s.image.name}… ${s.image.fitting.toFixed(1)} s`);
      await new Promise((r) => setTimeout(r, 250));
    }
  }

  // ---- a simulation, stepped live -------------------------------------------------------
  // The grid (a torus) as an image on the map; each frame asks the server for N more steps.
  async function startSimulation() {
    const sim = state.simulation;
    $('kind').textContent = `· ${sim.name} simulation`;
    for (const id of ['filter', 'periodic', 'seams', 'dl-view', 'dl-view-exr', 'dl-size', 'dl-wgsl', 'dl-model']) {
      const e = $(id); (e.closest('label') || e).style.display = 'none';
    }
    $('command').textContent = `spectex simulate file ${state.name} -o out.png   (with the spec below)`;
    map = L.map('map', { crs: L.CRS.Simple, minZoom: -4, maxZoom: 6, attributionControl: false });
    const bounds = [[0, 0], [-sim.height, sim.width]];
    const overlay = L.imageOverlay('', bounds).addTo(map);
    overlay.on('load', () => { overlay.getElement().style.imageRendering = 'pixelated'; });
    map.fitBounds(bounds);
    const seed = $('seed');
    seed.textContent = 'new seed (restart)';
    seed.addEventListener('click', async () => {
      try { state = await api('/api/sim/reset?reseed=1', {}); } catch (e) { showError(e.message); }
    });
    const controls = document.createElement('div');
    controls.innerHTML = '<label><input type="checkbox" id="sim-run" checked> running</label>' +
      '<div class="field"><span>steps per frame</span><input type="range" id="sim-steps" min="1" max="500" value="20" aria-label="steps per frame"><input type="number" id="sim-steps-num" value="20"></div>';
    $('panel').before(controls);
    $('sim-steps').addEventListener('input', (e) => { $('sim-steps-num').value = e.target.value; });
    $('sim-steps-num').addEventListener('change', (e) => { $('sim-steps').value = e.target.value; });
    const panel = $('panel');
    const rebuild = () => {
      panel.textContent = '';
      const saved = state.panel;
      state.panel = state.simulation.panel;
      build(panel, state.simulation.spec, '', 'simulation');
      state.panel = saved;
    };
    simSet = async (pointer, value, row) => {
      try { state = await api('/api/sim/set', { pointer, value }); row.classList.remove('bad'); showError(''); }
      catch (e) { row.classList.add('bad'); showError(e.message); }
    };
    rebuild();
    let frames = 0, t0 = performance.now();
    window.spectex.ready = true;
    for (;;) {
      if (!$('sim-run').checked) { await new Promise((r) => setTimeout(r, 200)); continue; }
      const steps = Number($('sim-steps').value) || 1;
      try {
        const r = await fetch(`/api/sim/frame.png?steps=${steps}&t=${frames}`);
        if (!r.ok) throw new Error((await r.text()).trim());
        const url = URL.createObjectURL(await r.blob());
        const old = overlay._url;
        overlay.setUrl(url);
        if (old && old.startsWith('blob:')) setTimeout(() => URL.revokeObjectURL(old), 1000);
        frames += 1;
        if (frames % 10 === 0) {
          const s = await api('/api/state');
          state = s;
          setStatus(`${s.simulation.steps_done} steps · ${(10000 / (performance.now() - t0)).toFixed(1)} frames/s`);
          t0 = performance.now();
        }
      } catch (e) { showError(e.message); await new Promise((r) => setTimeout(r, 1000)); }
    }
  }
  let simSet = null;

  // ---- start --------------------------------------------------------------------------
  async function start() {
    state = await api('/api/state');
    if (state.simulation) return startSimulation();
    if (state.image) state = await waitForFit();
    version = state.version;
    buildPanel();
    if (state.image) showImage(state);
    if (state.period) { opts.periodic = state.period; $('periodic').checked = true; $('period').value = state.period; }
    const [minZoom, maxZoom] = state.zoom;
    map = L.map('map', {
      crs: L.CRS.Simple, minZoom, maxZoom, zoomSnap: 1, zoomDelta: 1, attributionControl: false,
      fadeAnimation: false, keyboardPanDelta: 128,
      // Under automation (the browser test) headless Chromium drew no frames for the zoom
      // animation's CSS transitions, which then never ended: zoom without animation there.
      zoomAnimation: !navigator.webdriver,
    });
    const size = map.getSize();
    map.setView([-size.y / 2, size.x / 2], 0, { animate: false });
    // A coarse tile is the quarter-resolution twin of a fine one (the same region, 1/16 of the
    // pixels), so the coarse layer covers the view no further than the fine one does.
    coarse = new Layer('', { tileSize: state.tile, size: state.tile / 4, zoomOffset: -2, q: 'c', minZoom: minZoom + 2, maxZoom, keepBuffer: 0 });
    fine = new Layer('', { tileSize: state.tile, q: 'f', minZoom, maxZoom, keepBuffer: 1 });
    showInBatches();
    fine.on('tileload', () => { window.spectex.tilesLoaded += 1; });
    fine.on('loading', () => { window.spectex.loading = true; });
    fine.on('load', () => { window.spectex.loading = false; });
    coarse.addTo(map);
    fine.addTo(map);
    seams = L.layerGroup().addTo(map);
    window.spectex.map = map;
    fine.once('load', () => { window.spectex.ready = true; });
    // A jump (go to, or a view set farther than a pan reaches) makes Leaflet drop every tile
    // (`viewprereset`, after the layers' own handlers have removed them): the new view's grid is
    // anchored afresh, as at a redraw, so that it too needs the fewest tiles.
    map.on('viewprereset', () => {
      grid = new Map();
      fine._grid = grid;
      coarse._grid = grid;
    });
    map.on('moveend', () => { showWhere(); drawSeams(); postView(); });
    map.on('mousemove', (e) => {
      setStatus(`pointer at ${fmt(e.latlng.lng)}, ${fmt(-e.latlng.lat)}`);
    });
    setStatus(`${state.kind} model · tiles on the ${state.device} (${state.workers} workers)`);
    showWhere();
    postView();
    setInterval(postView, 5000);
    addEventListener('pagehide', () => navigator.sendBeacon('/api/close?s=' + session));
    $('goto').addEventListener('submit', (e) => {
      e.preventDefault();
      const m = $('goto-text').value.split(/[ ,]+/).map(Number);
      if (m.length !== 2 || !m.every(isFinite)) { showError('go to: write x,y, for example 1e7,1e7'); return; }
      showError('');
      // The point goes to the view's top-left corner, as `--offset` puts it.
      const z = map.getZoom(), s = map.getSize(), k = Math.pow(2, -z);
      map.setView([-(m[1] + (s.y / 2) * k), m[0] + (s.x / 2) * k], z, { animate: false });
    });
    $('filter').addEventListener('change', (e) => { opts.filter = e.target.checked; redraw(); });
    const periodic = () => {
      const text = $('period').value.trim();
      opts.periodic = $('periodic').checked && /^\d+x\d+$/.test(text) ? text : '';
      redraw();
    };
    $('periodic').addEventListener('change', periodic);
    $('period').addEventListener('change', periodic);
    $('seams').addEventListener('change', (e) => { opts.seams = e.target.checked; drawSeams(); });
    const setZ = (v) => { opts.z = Number(v); $('z').value = v; $('z-num').value = v; redraw(); };
    $('z').addEventListener('change', (e) => setZ(e.target.value));
    $('z-num').addEventListener('change', (e) => setZ(e.target.value));
    $('seed').addEventListener('click', async () => {
      try { applyState(await api('/api/seed', {}), true); } catch (e) { showError(e.message); }
    });
    $('dl-size').addEventListener('submit', (e) => {
      e.preventDefault();
      const q = windowQuery({ download: 1, w: $('dl-w').value, h: $('dl-h').value, format: $('dl-format').value });
      location.href = '/render?' + q;
    });
  }

  start().catch((e) => { setStatus('error: ' + e.message); });
})();
