// The real-browser test of `spectex view` (run by xtask/src/browser.rs): headless Chromium,
// driven by playwright-core with the system's browser, loads the page, pans, zooms out 16×,
// moves a slider and goes to (1e7, 1e7), and checks each time from a screenshot of the map that
// the view is not blank, changed, and equals `spectex render` of the window the page shows.
//
// With BENCH set it measures redraws instead (`cargo xtask view-bench`, see `bench`).
//
// Environment: PLAYWRIGHT_CORE (the package's directory), CHROMIUM, SPECTEX (the binary),
// VIEW_URL, MODEL (the model file the server shows), SLIDER (the JSON pointer of the field whose
// slider moves), OUT (a scratch directory); SHOTS (a
// directory for the README's screenshots) with MODEL_SHOT_URL and IMAGE_URL (views of a model
// and of an image) optionally.
'use strict';
const pw = require(process.env.PLAYWRIGHT_CORE);
const { execFileSync } = require('child_process');
const fs = require('fs');
const path = require('path');

const OUT = process.env.OUT;
const ARGS = ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync'];
const results = [];

function fail(message) { throw new Error(message); }

// Waits until `fn(arg)` holds in the page, polling from Node.
async function until(page, fn, arg, ms) {
  const end = Date.now() + ms;
  for (;;) {
    if (await page.evaluate(fn, arg)) return;
    if (Date.now() > end) fail(`timed out after ${ms} ms waiting for ${String(fn).slice(0, 120)}`);
    await page.waitForTimeout(50);
  }
}

// Waits until the fine layer has loaded the view's tiles and no image is pending, then two
// frames.
async function settle(page) {
  await until(page, () => {
    const tiles = document.querySelectorAll('#map .leaflet-tile');
    return !window.spectex.loading && tiles.length > 0 && [...tiles].every((t) => t.complete);
  }, undefined, 120000);
  await page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));
}

// `spectex render MODEL` of the window the page shows, as PNG bytes.
function cliRender(model, v, name) {
  const out = path.join(OUT, `${name}-cli.png`);
  execFileSync(process.env.SPECTEX, ['render', model, '-o', out, '--size', `${v.w}x${v.h}`,
    '--offset', `${v.x},${v.y}`, '--scale', String(v.scale)], { stdio: ['ignore', 'ignore', 'inherit'] });
  return fs.readFileSync(out);
}

// A non-interlaced 8-bit PNG (grey, grey+alpha, RGB or RGBA: what Chromium and `spectex render`
// write) decoded to its first channel, row-major: { w, h, v }.
function decodePng(buf) {
  const zlib = require('zlib');
  let pos = 8, w = 0, h = 0, type = 0, depth = 0, interlace = 0;
  const idat = [];
  while (pos < buf.length) {
    const len = buf.readUInt32BE(pos), kind = buf.toString('ascii', pos + 4, pos + 8);
    const data = buf.subarray(pos + 8, pos + 8 + len);
    if (kind === 'IHDR') {
      w = data.readUInt32BE(0); h = data.readUInt32BE(4); depth = data[8]; type = data[9]; interlace = data[12];
    } else if (kind === 'IDAT') idat.push(data);
    pos += 12 + len;
  }
  const bpp = { 0: 1, 4: 2, 2: 3, 6: 4 }[type];
  if (depth !== 8 || !bpp || interlace) fail(`unsupported PNG (depth ${depth}, colour type ${type}, interlace ${interlace})`);
  const raw = zlib.inflateSync(Buffer.concat(idat));
  const stride = w * bpp, out = Buffer.alloc(stride * h), v = new Uint8Array(w * h);
  for (let y = 0; y < h; y++) {
    const f = raw[y * (stride + 1)], row = raw.subarray(y * (stride + 1) + 1, (y + 1) * (stride + 1));
    const cur = out.subarray(y * stride, (y + 1) * stride), prev = y ? out.subarray((y - 1) * stride, y * stride) : null;
    for (let i = 0; i < stride; i++) {
      const a = i >= bpp ? cur[i - bpp] : 0, b = prev ? prev[i] : 0, c = prev && i >= bpp ? prev[i - bpp] : 0;
      let x = row[i];
      if (f === 1) x += a; else if (f === 2) x += b; else if (f === 3) x += (a + b) >> 1;
      else if (f === 4) { const p = a + b - c, pa = Math.abs(p - a), pb = Math.abs(p - b), pc = Math.abs(p - c); x += pa <= pb && pa <= pc ? a : pb <= pc ? b : c; }
      cur[i] = x & 255;
    }
    for (let x = 0; x < w; x++) v[y * w + x] = cur[x * bpp];
  }
  return { w, h, v };
}

// Per-pixel statistics of two PNGs (first channel: the models here are grey): mean and max
// |a − b|, the share of pixels differing by more than 2 levels, and the standard deviation of
// `a` (0 for a blank view).
function compare(a, b) {
  const x = decodePng(a), y = b ? decodePng(b) : null;
  let sum = 0, sum2 = 0, diff = 0, max = 0, off = 0;
  const n = x.w * x.h;
  for (let i = 0; i < n; i++) {
    const v = x.v[i];
    sum += v; sum2 += v * v;
    if (y) {
      const e = Math.abs(v - y.v[i]);
      diff += e; max = Math.max(max, e); off += e > 2 ? 1 : 0;
    }
  }
  const mean = sum / n;
  return {
    size: [x.w, x.h], other: y ? [y.w, y.h] : null, std: Math.sqrt(Math.max(0, sum2 / n - mean * mean)),
    meanDiff: y ? diff / n : null, maxDiff: y ? max : null, offShare: y ? off / n : null,
  };
}

// Screenshot of the map, compared with the CLI's render of the same window (and with `before`).
async function check(page, name, model, before) {
  await settle(page);
  const v = await page.evaluate(() => window.spectex.view());
  const hide = await page.addStyleTag({ content: '.leaflet-control-container { display: none; }' });
  const shot = await page.locator('#map').screenshot();
  await hide.evaluate((e) => e.remove());
  fs.writeFileSync(path.join(OUT, `${name}.png`), shot);
  const cli = cliRender(model, v, name);
  const c = compare(shot, cli);
  const line = { name, window: v, ...c };
  if (before) line.changedBy = compare(shot, before).meanDiff;
  results.push(line);
  console.log(`browser: ${name}: window ${v.w}x${v.h} at ${v.x},${v.y} scale ${v.scale}: ` +
    `std ${c.std.toFixed(1)}, mean |screenshot - CLI| ${c.meanDiff.toFixed(3)}, max ${c.maxDiff}, ` +
    `${(100 * c.offShare).toFixed(3)}% pixels off by > 2` +
    (before ? `, changed by ${line.changedBy.toFixed(1)} levels on average` : ''));
  if (c.size[0] !== c.other[0] || c.size[1] !== c.other[1]) fail(`${name}: screenshot ${c.size} vs render ${c.other}`);
  if (c.std < 3) fail(`${name}: the view is blank (std ${c.std})`);
  if (c.offShare > 0.001 || c.meanDiff > 0.05) fail(`${name}: the view differs from spectex render`);
  if (before && line.changedBy < 2) fail(`${name}: the view did not change`);
  return shot;
}

async function main() {
  const browser = await pw.chromium.launch({ executablePath: process.env.CHROMIUM, args: ARGS, headless: true });
  try {
    // A MAP_W × MAP_H map (default 1024 × 1024; the sidebar is 380 px wide).
    const ctx = await browser.newContext({ viewport: { width: 380 + Number(process.env.MAP_W || 1024), height: Number(process.env.MAP_H || 1024) }, deviceScaleFactor: 1 });
    const page = await ctx.newPage();
    page.on('pageerror', (e) => { console.log('browser: page error: ' + e.message); process.exitCode = 1; });
    const model = process.env.MODEL;
    const t0 = Date.now();
    await page.goto(process.env.VIEW_URL);
    await until(page, () => window.spectex && window.spectex.ready, undefined, 120000);
    const firstView = Date.now() - t0;
    console.log(`browser: first full view (page load included): ${firstView} ms`);
    const origin = await check(page, 'origin', model);

    // Pan: drag by (−300, −180), slowly (no inertia).
    const box = await page.locator('#map').boundingBox();
    const cx = box.x + box.width / 2, cy = box.y + box.height / 2;
    await page.mouse.move(cx, cy);
    await page.mouse.down();
    await page.mouse.move(cx - 300, cy - 180, { steps: 20 });
    await page.waitForTimeout(200);
    await page.mouse.up();
    const panned = await check(page, 'panned', model, origin);
    const pv = await page.evaluate(() => window.spectex.view());
    if (pv.x !== 300 || pv.y !== 180) fail(`panned: the view is at ${pv.x},${pv.y}, not 300,180`);

    // Zoom out 16×: four clicks on the map's − button.
    for (let i = 0; i < 4; i++) {
      const z = await page.evaluate(() => window.spectex.view().scale);
      await page.click('.leaflet-control-zoom-out');
      await until(page, (z) => window.spectex.view().scale === 2 * z, z, 10000);
    }
    const t1 = Date.now();
    const zoomed = await check(page, 'zoomed-out-16x', model, panned);
    console.log(`browser: zoomed out 16x, full view settled ${Date.now() - t1} ms after the last zoom step`);
    if ((await page.evaluate(() => window.spectex.view().scale)) !== 16) fail('zoom: scale is not 16');

    // Move a slider (SLIDER, a field's JSON pointer), by a click on its track.
    await page.evaluate(() => document.querySelectorAll('details').forEach((d) => { d.open = true; }));
    const slider = page.locator(`input[type=range][aria-label="${process.env.SLIDER}"]`);
    const redraws = await page.evaluate(() => window.spectex.redraws.length);
    await slider.scrollIntoViewIfNeeded();
    const sb = await slider.boundingBox();
    await page.mouse.click(sb.x + sb.width * 0.8, sb.y + sb.height / 2);
    await until(page, (n) => {
      const r = window.spectex.redraws;
      return r.length > n && r[r.length - 1].fine != null;
    }, redraws, 60000);
    const redraw = await page.evaluate(() => window.spectex.redraws[window.spectex.redraws.length - 1]);
    console.log(`browser: slider moved: redrawn (zoomed out 16x) in ${Math.round(redraw.fine)} ms, coarse tiles in ${Math.round(redraw.coarse)} ms`);
    // A redraw anchors the tile grid to the view: this one (panned, then zoomed out around its
    // centre, so off the world's 256-pixel grid) loads the fewest tiles a view of its size can
    // have, as one at the origin does, in each layer.
    const sv = await page.evaluate(() => window.spectex.view());
    const fewest = Math.ceil(sv.w / 256) * Math.ceil(sv.h / 256);
    console.log(`browser: slider moved: view at pixel ${sv.px},${sv.py}; ${redraw.tiles.coarse} coarse + ${redraw.tiles.fine} fine tiles (fewest ${fewest})`);
    if (sv.px % 256 === 0 || sv.py % 256 === 0) fail(`slider: the view at pixel ${sv.px},${sv.py} is on the world's grid; the check needs one off it`);
    if (redraw.tiles.coarse !== fewest || redraw.tiles.fine !== fewest) fail('slider: the redraw loaded more tiles than the view needs: the grid is not anchored to it');
    // The view's top-left pixel is the corner of a tile (here the map's centre is a fraction of
    // a pixel, which Leaflet floors where the map rounds).
    const anchor = await page.evaluate(() => window.spectex.anchor());
    const mod = (a) => ((a % 256) + 256) % 256;
    if (anchor.x !== mod(sv.px) || anchor.y !== mod(sv.py)) fail(`slider: the grid's offset ${anchor.x},${anchor.y} is not the view's top-left pixel ${sv.px},${sv.py} mod 256`);
    const edited = path.join(OUT, 'edited.json');
    fs.writeFileSync(edited, await page.evaluate(async () => (await fetch('/api/model.json')).text()));
    const slid = await check(page, 'slider', edited, zoomed);

    // Go to (1e7, 1e7) and zoom back in to 1:1.
    await page.fill('#goto-text', '1e7,1e7');
    await page.press('#goto-text', 'Enter');
    await until(page, () => window.spectex.view().x === 1e7, undefined, 10000);
    const far = await check(page, 'goto-1e7', edited, slid);
    // The jump dropped every tile: the grid is anchored to the new view, as at a redraw.
    const jumped = await page.evaluate(() => ({ a: window.spectex.anchor(), v: window.spectex.view() }));
    if (jumped.a.x !== mod(jumped.v.px) || jumped.a.y !== mod(jumped.v.py)) fail(`goto-1e7: the grid's offset ${jumped.a.x},${jumped.a.y} is not the view's top-left pixel ${jumped.v.px},${jumped.v.py} mod 256`);
    for (let i = 0; i < 4; i++) {
      const z = await page.evaluate(() => window.spectex.view().scale);
      await page.click('.leaflet-control-zoom-in');
      await until(page, (z) => window.spectex.view().scale === z / 2, z, 10000);
    }
    await page.evaluate(() => { window.spectex.redraws.length = 0; });
    const t2 = Date.now();
    await check(page, 'near-1e7-1to1', edited, far);
    console.log(`browser: near 1e7 at 1:1, full view settled ${Date.now() - t2} ms after the last zoom step`);

    if (process.env.SHOTS) await screenshots(browser);
    fs.writeFileSync(path.join(OUT, 'results.json'), JSON.stringify(results, null, 1));
  } finally {
    await browser.close();
  }
}

// The README's two screenshots: a model (MODEL_SHOT_URL) with its nested panel open, and an
// image (IMAGE_URL) with its fit and spectra, the texture magnified 2× (smoother, smaller files).
async function screenshots(browser) {
  const ctx = await browser.newContext({ viewport: { width: 820, height: 470 }, deviceScaleFactor: 1 });
  const page = await ctx.newPage();
  const open = async (url) => {
    await page.goto(url);
    await until(page, () => window.spectex && window.spectex.ready, undefined, 120000);
    await settle(page);
  };
  await open(process.env.MODEL_SHOT_URL);
  await page.evaluate(() => { document.querySelector('#panel details').open = true; });
  await page.screenshot({ path: path.join(process.env.SHOTS, 'view-model.png') });
  await page.setViewportSize({ width: 960, height: 560 });
  await open(process.env.IMAGE_URL);
  await page.evaluate(() => window.spectex.map.zoomIn());
  await until(page, () => window.spectex.view().scale === 0.5, undefined, 10000);
  await settle(page);
  await until(page, () => [...document.querySelectorAll('#image img')].every((i) => i.complete && i.naturalWidth > 0), undefined, 60000);
  await page.screenshot({ path: path.join(process.env.SHOTS, 'view-image.png') });
  console.log(`browser: screenshots written to ${process.env.SHOTS}`);
}

// CPU time (ms) so far of the browser (this script's descendants) and of the server
// (SERVER_PID), from /proc (null elsewhere): on a 2-core machine the browser's share is the
// render's loss.
function cpuMs() {
  if (!fs.existsSync('/proc/self/stat')) return null;
  const procs = new Map();
  for (const pid of fs.readdirSync('/proc').filter((d) => /^\d+$/.test(d))) {
    try {
      const stat = fs.readFileSync(`/proc/${pid}/stat`, 'utf8').split(') ')[1].split(' ');
      procs.set(pid, { parent: stat[1], ms: 10 * (Number(stat[11]) + Number(stat[12])) });
    } catch (e) { /* the process ended */ }
  }
  const browser = (pid) => {
    for (let p = procs.get(pid)?.parent; p && p !== '0'; p = procs.get(p)?.parent) if (p === String(process.pid)) return true;
    return false;
  };
  const out = { chromium: 0, server: procs.get(process.env.SERVER_PID)?.ms ?? 0 };
  for (const [pid, p] of procs) if (browser(pid)) out.chromium += p.ms;
  return out;
}

// `cargo xtask view-bench`: REDRAWS clicks on "new seed" (PAN: the view moved by X,Y pixels
// first; ZOOM: at that zoom level), each redraw's times as the page records them (coarse and
// fine, from the redraw's start; from the click too) with its tiles' server timings summed, then
// best and median.
async function bench() {
  const browser = await pw.chromium.launch({ executablePath: process.env.CHROMIUM, args: ARGS, headless: true });
  try {
    const ctx = await browser.newContext({ viewport: { width: 380 + Number(process.env.MAP_W), height: Number(process.env.MAP_H) }, deviceScaleFactor: 1 });
    const page = await ctx.newPage();
    page.on('pageerror', (e) => { console.log('bench: page error: ' + e.message); process.exitCode = 1; });
    await page.goto(process.env.VIEW_URL);
    await until(page, () => window.spectex && window.spectex.ready, undefined, 120000);
    if (process.env.ZOOM) await page.evaluate((z) => window.spectex.map.setZoom(z, { animate: false }), Number(process.env.ZOOM));
    if (process.env.PAN) await page.evaluate((p) => window.spectex.map.panBy(p, { animate: false }), process.env.PAN.split(',').map(Number));
    await settle(page);
    const v = await page.evaluate(() => window.spectex.view());
    console.log(`bench: window ${v.w}x${v.h} at ${v.x},${v.y} scale ${v.scale}, ${process.env.REDRAWS} redraws after "new seed"`);
    const rows = [];
    const cpu0 = cpuMs();
    for (let i = 0; i < Number(process.env.REDRAWS); i++) {
      await page.waitForTimeout(300);
      const n = await page.evaluate(() => window.spectex.redraws.length);
      const clicked = Date.now();
      await page.click('#seed');
      // Waiting inside the page: a DevTools round trip every few ms would take the CPU measured.
      await page.evaluate((n) => new Promise((resolve) => {
        const id = setInterval(() => {
          const r = window.spectex.redraws;
          if (r.length > n && r[r.length - 1].fine != null) { clearInterval(id); resolve(); }
        }, 10);
      }), n);
      const click = Date.now() - clicked;
      const r = await page.evaluate(() => window.spectex.redraws[window.spectex.redraws.length - 1]);
      rows.push({ coarse: r.coarse, fine: r.fine, click });
      // (A page older than the tile timings records none.)
      const tiles = r.tiles ? `; tiles ${r.tiles.coarse} coarse + ${r.tiles.fine} fine, server ms summed: ` +
        Object.entries(r.tiles.server).map(([k, ms]) => `${k} ${ms}`).join(', ') : '';
      console.log(`bench: redraw ${i + 1}: coarse ${Math.round(r.coarse)} ms, full ${Math.round(r.fine)} ms ` +
        `(${click} ms from the click)${tiles}`);
    }
    const cpu1 = cpuMs();
    if (cpu0) {
      const per = (k) => Math.round((cpu1[k] - cpu0[k]) / rows.length);
      console.log(`bench: CPU per redraw: server ${per('server')} ms, Chromium ${per('chromium')} ms`);
    }
    for (const k of ['coarse', 'fine', 'click']) {
      const a = rows.map((r) => r[k]).sort((x, y) => x - y);
      const name = { coarse: 'coarse tiles', fine: 'full view', click: 'full view from the click' }[k];
      console.log(`bench: ${name}: best ${Math.round(a[0])} ms, median ${Math.round(a[a.length >> 1])} ms, worst ${Math.round(a[a.length - 1])} ms`);
    }
  } finally {
    await browser.close();
  }
}

(process.env.BENCH ? bench() : main()).catch((e) => { console.error('browser: FAILED: ' + e.message); process.exit(1); });
