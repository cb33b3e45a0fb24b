// End-to-end test of the viewer in headless Chromium (Debian's, driven by playwright-core).
//
//   node test/e2e.mjs            (from viewer/, after `npm ci` and a release build)
//
// Writes a .glb with `subsurf tessellate` (SUBSURF_BIN, default the release build in
// CARGO_TARGET_DIR or ../target) and checks it with the Khronos glTF validator; serves
// viewer/ and the file on 127.0.0.1, loads index.html?model=..., and checks the pictures:
// not blank, the model fitted in view, the zebra and control-mesh toggles change them,
// dragging orbits; then opens the file through the file input; and a textured model (the
// torus, with TEXCOORD_0) whose checker toggle changes the picture. Requests to anything but
// the local server are blocked. The whole run is limited to 60 s. Prints
// `viewer-e2e: N passed, M failed` last and exits 1 on any failure.
// VIEWER_SCREENSHOTS=DIR keeps two screenshots there. SUBSURF_GALLERY=DIR (a folder written
// by `subsurf demo -o DIR`) also checks the demo gallery: its page loads without errors,
// every picture decodes, every link it makes resolves.

import { spawnSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, existsSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import validator from 'gltf-validator';
import { startServer } from '../serve.mjs';

const VIEWER = resolve(dirname(fileURLToPath(import.meta.url)), '..');
const REPO = resolve(VIEWER, '..');
const TARGET = resolve(REPO, process.env.CARGO_TARGET_DIR ?? 'target');
const BIN = process.env.SUBSURF_BIN ?? join(TARGET, 'release', 'subsurf');
const CHROMIUM = process.env.CHROMIUM ?? '/usr/bin/chromium';
const SHAPE = join(REPO, 'crates/subsurf/tests/shapes/osd/catmark_cube.obj');
const TEXTURED = join(REPO, 'examples/meshes/torus.obj');
const UNTEXTURED = join(REPO, 'examples/meshes/cube.obj');
const TIME_LIMIT_MS = 60_000;
const VIEW = { width: 800, height: 600 };
const BACKGROUND = [0xf2, 0xf2, 0xf2];

const started = Date.now();
const killer = setTimeout(() => {
  console.error(`viewer e2e: timed out after ${TIME_LIMIT_MS / 1000} s`);
  console.log('viewer-e2e: 0 passed, 1 failed');
  process.exit(1);
}, TIME_LIMIT_MS);

let passed = 0;
let failed = 0;
async function check(name, fn) {
  const t0 = Date.now();
  try {
    const note = await fn();
    passed++;
    console.log(`ok - ${name}${note ? ` (${note})` : ''} [${Date.now() - t0} ms]`);
  } catch (e) {
    failed++;
    console.log(`not ok - ${name}: ${e.message}`);
  }
}
function assert(cond, message) {
  if (!cond) throw new Error(message);
}

const tmp = mkdtempSync(join(tmpdir(), 'subsurf-viewer-'));
const glb = join(tmp, 'cube.glb');
const torus = join(tmp, 'torus.glb');
const plainCube = join(tmp, 'plain.glb');
let server;
let context;
try {
  // 1. The model.
  assert(existsSync(BIN), `no subsurf binary at ${BIN} (cargo build --release first)`);
  const run = spawnSync(
    BIN,
    ['tessellate', SHAPE, '-o', glb, '--rate', '8', '--control-mesh'],
    { encoding: 'utf8', timeout: 20_000 },
  );
  assert(run.status === 0, `subsurf tessellate failed (${run.status}): ${run.stderr}`);
  for (const [input, output] of [[TEXTURED, torus], [UNTEXTURED, plainCube]]) {
    const r = spawnSync(BIN, ['tessellate', input, '-o', output, '--rate', '8'], {
      encoding: 'utf8',
      timeout: 20_000,
    });
    assert(r.status === 0, `subsurf tessellate ${input} failed (${r.status}): ${r.stderr}`);
  }

  for (const file of [glb, torus]) {
    await check(`${file.split('/').pop()} passes the Khronos glTF validator`, async () => {
      const report = await validator.validateBytes(new Uint8Array(readFileSync(file)));
      const i = report.issues;
      const first = i.messages.slice(0, 3).map((m) => `${m.code} ${m.pointer ?? ''}`);
      assert(i.numErrors === 0 && i.numWarnings === 0, `${i.numErrors} errors, ${i.numWarnings} warnings: ${first}`);
      return `${report.info.totalTriangleCount ?? '?'} triangles, ${i.numInfos} infos, ${i.numHints} hints`;
    });
  }

  // 2. The browser, on the local server only.
  server = await startServer({ root: VIEWER, models: [glb, torus, plainCube] });
  context = await chromium.launchPersistentContext(join(tmp, 'profile'), {
    executablePath: CHROMIUM,
    headless: true,
    viewport: VIEW,
    timeout: 20_000,
    args: [
      '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      // WebGL without a GPU: SwiftShader, which recent Chromium enables only on request.
      '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    ],
  });
  context.setDefaultTimeout(15_000);
  const blocked = [];
  const allowed = new Set([new URL(server.url).origin]); // local servers only
  await context.route('**/*', (route) => {
    const url = new URL(route.request().url());
    if (allowed.has(url.origin) || url.protocol === 'data:') return route.continue();
    blocked.push(url.href);
    return route.abort();
  });
  const page = context.pages()[0] ?? (await context.newPage());
  const errors = [];
  page.on('pageerror', (e) => errors.push(`pageerror: ${e.message}`));
  page.on('console', (m) => m.type() === 'error' && errors.push(`console: ${m.text()}`));

  // Pixel statistics are computed in a second page (a 2D canvas decodes the PNGs).
  const lab = await context.newPage();
  await lab.goto('about:blank');
  const analyse = (a, b) =>
    lab.evaluate(
      async ({ a, b, bg }) => {
        const pixels = async (png) => {
          const img = new Image();
          img.src = `data:image/png;base64,${png}`;
          await img.decode();
          const c = new OffscreenCanvas(img.width, img.height);
          const g = c.getContext('2d');
          g.drawImage(img, 0, 0);
          return { w: img.width, h: img.height, d: g.getImageData(0, 0, img.width, img.height).data };
        };
        const A = await pixels(a);
        const B = b ? await pixels(b) : null;
        const s = { total: A.w * A.h, foreground: 0, dark: 0, blue: 0, changed: 0 };
        let [x0, y0, x1, y1] = [A.w, A.h, -1, -1];
        for (let i = 0, p = 0; i < A.d.length; i += 4, p++) {
          const [r, g, bl] = [A.d[i], A.d[i + 1], A.d[i + 2]];
          if (Math.max(Math.abs(r - bg[0]), Math.abs(g - bg[1]), Math.abs(bl - bg[2])) > 12) {
            s.foreground++;
            const x = p % A.w;
            const y = Math.floor(p / A.w);
            [x0, y0, x1, y1] = [Math.min(x0, x), Math.min(y0, y), Math.max(x1, x), Math.max(y1, y)];
          }
          if (r + g + bl < 120) s.dark++;
          if (bl > r + 60 && bl > g + 40) s.blue++;
          if (B && Math.max(...[0, 1, 2].map((k) => Math.abs(A.d[i + k] - B.d[i + k]))) > 24) s.changed++;
        }
        s.box = { x0, y0, x1, y1, w: A.w, h: A.h };
        return s;
      },
      { a, b, bg: BACKGROUND },
    );

  // The canvas as the viewer draws it (the page's own snapshot: a PNG of the WebGL canvas).
  const shot = async () => {
    const url = await page.evaluate(() => window.__snapshot());
    return url.slice(url.indexOf(',') + 1);
  };
  // A real screenshot of the page, below the toolbar (slower: about 2 s headless).
  const screenshot = async () => {
    const bar = await page.locator('#bar').boundingBox();
    const top = Math.ceil(bar.y + bar.height + 4);
    const png = await page.screenshot({ clip: { x: 0, y: top, width: VIEW.width, height: VIEW.height - top } });
    return png.toString('base64');
  };
  const waitReady = async () => {
    await page.waitForFunction(() => window.__viewerReady === true || window.__viewerError, null, {
      timeout: 20_000,
    });
    const err = await page.evaluate(() => window.__viewerError);
    assert(!err, `viewer error: ${err}`);
  };
  const pct = (n, s) => `${((100 * n) / s.total).toFixed(2)}%`;

  let shaded;
  let shadedStats;
  await check('loads ?model=... and reports ready', async () => {
    await page.goto(`${server.url}index.html?model=models/cube.glb`);
    await waitReady();
    const text = await page.locator('#status').textContent();
    assert(/cube\.glb: 768 triangles/.test(text), `status: ${text}`);
    return text;
  });

  await check('the page shows the model (screenshot not blank)', async () => {
    const s = await analyse(await screenshot());
    assert(s.foreground > 0.03 * s.total, `only ${pct(s.foreground, s)} non-background pixels`);
    return `${pct(s.foreground, s)} non-background`;
  });

  await check('the canvas shows the model (not blank)', async () => {
    shaded = await shot();
    shadedStats = await analyse(shaded);
    assert(shadedStats.foreground > 0.03 * shadedStats.total, `only ${pct(shadedStats.foreground, shadedStats)} non-background pixels`);
    return `${pct(shadedStats.foreground, shadedStats)} non-background`;
  });

  await check('the camera is fitted to the model', async () => {
    const b = shadedStats.box;
    const [w, h] = [b.x1 - b.x0 + 1, b.y1 - b.y0 + 1];
    assert(b.x0 > 0 && b.y0 > 0 && b.x1 < b.w - 1 && b.y1 < b.h - 1, `model touches the border: ${JSON.stringify(b)}`);
    assert(Math.max(w / b.w, h / b.h) > 0.4, `model too small: ${w}×${h} of ${b.w}×${b.h}`);
    return `${w}×${h} of ${b.w}×${b.h} px`;
  });

  await check('the control mesh is drawn, and hiding it changes the picture', async () => {
    assert(shadedStats.blue > 200, `only ${shadedStats.blue} control-mesh (blue) pixels`);
    await page.locator('#control').click(); // the real checkbox
    assert((await page.locator('#control').isChecked()) === false, 'checkbox still checked');
    const hidden = await shot();
    const s = await analyse(hidden, shaded);
    assert(s.blue < 0.05 * shadedStats.blue, `${s.blue} blue pixels left (of ${shadedStats.blue})`);
    assert(s.changed > 0.5 * shadedStats.blue, `only ${s.changed} pixels changed`);
    await page.evaluate(() => window.__toggleControlMesh(true));
    const back = await analyse(await shot(), shaded);
    assert(back.changed < 0.001 * back.total, `showing it again differs in ${back.changed} pixels`);
    return `${shadedStats.blue} line pixels; ${s.changed} pixels changed`;
  });

  await check('the zebra toggle changes the picture substantially', async () => {
    await page.evaluate(() => window.__toggleZebra(true));
    assert(await page.locator('#zebra').isChecked(), 'zebra checkbox not checked');
    const striped = await shot();
    const s = await analyse(striped, shaded);
    assert(s.changed > 0.3 * shadedStats.foreground, `only ${pct(s.changed, s)} pixels changed`);
    assert(s.dark > 0.05 * shadedStats.foreground, `only ${s.dark} dark (stripe) pixels`);
    await page.locator('#zebra').click();
    const back = await analyse(await shot(), shaded);
    assert(back.changed < 0.001 * back.total, `switching it off differs in ${back.changed} pixels`);
    return `${pct(s.changed, s)} pixels changed, ${pct(s.dark, s)} dark`;
  });

  await check('dragging orbits the camera', async () => {
    await page.mouse.move(400, 350);
    await page.mouse.down();
    await page.mouse.move(520, 380, { steps: 2 });
    await page.mouse.up();
    const s = await analyse(await shot(), shaded);
    // The light follows the camera and the limit surface is nearly round: mostly the
    // control mesh's lines move.
    assert(s.changed > 0.5 * shadedStats.blue, `only ${s.changed} pixels changed`);
    assert(s.foreground > 0.5 * shadedStats.foreground, 'the model left the view');
    return `${pct(s.changed, s)} pixels changed`;
  });

  await check('opens a .glb through the file input', async () => {
    await page.goto(`${server.url}index.html`);
    await page.locator('#file').setInputFiles(glb);
    await waitReady();
    const text = await page.locator('#status').textContent();
    assert(/cube\.glb: 768 triangles/.test(text), `status: ${text}`);
    const s = await analyse(await shot(), shaded);
    assert(s.changed < 0.01 * s.total, `differs from the ?model= picture in ${pct(s.changed, s)}`);
  });

  await check('the checker is offered for a textured model only, and changes its picture', async () => {
    await page.goto(`${server.url}index.html?model=models/plain.glb`);
    await waitReady();
    assert(await page.locator('#checker').isDisabled(), 'checker enabled for an untextured model');
    await page.goto(`${server.url}index.html?model=models/torus.glb`);
    await waitReady();
    assert(!(await page.locator('#checker').isDisabled()), 'checker disabled for the textured torus');
    const plain = await shot();
    const plainStats = await analyse(plain);
    await page.locator('#checker').click();
    const s = await analyse(await shot(), plain);
    assert(s.changed > 0.2 * plainStats.foreground, `only ${pct(s.changed, s)} pixels changed`);
    await page.evaluate(() => window.__toggleChecker(false));
    const back = await analyse(await shot(), plain);
    assert(back.changed < 0.001 * back.total, `switching it off differs in ${back.changed} pixels`);
    return `${pct(s.changed, s)} pixels changed`;
  });

  if (process.env.SUBSURF_GALLERY) {
    await check('the demo gallery: every picture decodes, every link resolves', async () => {
      const gallery = await startServer({ root: resolve(process.env.SUBSURF_GALLERY) });
      allowed.add(new URL(gallery.url).origin);
      try {
        await page.goto(`${gallery.url}index.html`, { waitUntil: 'load' });
        const r = await page.evaluate(async () => {
          const imgs = [...document.querySelectorAll('figure img')];
          await Promise.all(imgs.map((i) => i.decode().catch(() => {})));
          const broken = imgs.filter((i) => !(i.complete && i.naturalWidth > 0)).map((i) => i.src);
          const links = [...new Set([...document.querySelectorAll('a[href]')]
            .map((a) => a.href)
            .filter((h) => h.startsWith(location.origin)))];
          const dead = [];
          for (const h of links) {
            const res = await fetch(h.split('#')[0], { method: 'HEAD' });
            if (!res.ok) dead.push(`${h} (${res.status})`);
          }
          const captions = [...document.querySelectorAll('figcaption')].filter((c) => c.textContent.trim());
          return { images: imgs.length, broken, links: links.length, dead, captions: captions.length };
        });
        assert(r.images >= 20, `only ${r.images} pictures`);
        assert(r.broken.length === 0, `pictures that do not decode: ${r.broken.slice(0, 5)}`);
        assert(r.dead.length === 0, `links that do not resolve: ${r.dead.slice(0, 5)}`);
        assert(r.captions >= r.images, `${r.captions} captions for ${r.images} pictures`);
        // A click enlarges a picture with its caption; Escape closes it.
        await page.locator('figure a').first().click();
        const shown = await page.evaluate(async () => {
          const box = document.getElementById('lightbox');
          const img = box.querySelector('img');
          await img.decode().catch(() => {});
          const caption = document.querySelector('figure figcaption').textContent;
          return { open: !box.hidden, decoded: img.naturalWidth > 0, same: box.querySelector('p').textContent === caption };
        });
        assert(shown.open && shown.decoded && shown.same, `lightbox: ${JSON.stringify(shown)}`);
        await page.keyboard.press('Escape');
        assert(await page.evaluate(() => document.getElementById('lightbox').hidden), 'Escape left it open');
        return `${r.images} pictures, ${r.links} links, the lightbox opens and closes`;
      } finally {
        await gallery.close();
      }
    });
  }

  await check('no page errors and no request left the machine', async () => {
    assert(errors.length === 0, errors.slice(0, 5).join('; '));
    assert(blocked.length === 0, `blocked: ${blocked.slice(0, 5).join(', ')}`);
  });

  if (process.env.VIEWER_SCREENSHOTS) {
    // Keep the pictures for a person to look at.
    const { writeFileSync, mkdirSync } = await import('node:fs');
    const dir = resolve(process.env.VIEWER_SCREENSHOTS);
    mkdirSync(dir, { recursive: true });
    await page.goto(`${server.url}index.html?model=models/cube.glb`);
    await waitReady();
    writeFileSync(join(dir, 'shaded.png'), await page.screenshot());
    await page.evaluate(() => window.__toggleZebra(true));
    writeFileSync(join(dir, 'zebra.png'), await page.screenshot());
  }
} catch (e) {
  failed++;
  console.log(`not ok - setup: ${e.message}`);
} finally {
  await context?.close().catch(() => {});
  await server?.close();
  rmSync(tmp, { recursive: true, force: true });
  clearTimeout(killer);
}
console.log(`viewer e2e: finished in ${((Date.now() - started) / 1000).toFixed(1)} s`);
console.log(`viewer-e2e: ${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
