// The web inspector in headless Chromium (web/test.sh runs this): the page loads, renders,
// traces a clicked pixel to the tree `raytree trace --json` gives, exports what the CLI
// writes, survives hostile input and deep recursion, and reports its frame times.
//
// Environment: RAYTREE_BIN (the native `raytree`), RAYTREE_DIST (web/dist), RAYTREE_OUT
// (screenshots, downloads and measurements; default web/test-out).
import { chromium } from 'playwright-core';
import { execFileSync } from 'node:child_process';
import { createServer } from 'node:http';
import { mkdtempSync, mkdirSync, readFileSync, writeFileSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, extname, dirname } from 'node:path';
import { fileURLToPath } from 'node:url';
import assert from 'node:assert/strict';

const here = dirname(fileURLToPath(import.meta.url));
const root = dirname(here);
const dist = process.env.RAYTREE_DIST ?? join(here, 'dist');
const out = process.env.RAYTREE_OUT ?? join(here, 'test-out');
const bin = process.env.RAYTREE_BIN ?? join(root, 'target/release/raytree');
mkdirSync(out, { recursive: true });

// A pixel of the classic scene's glass ball (a 17-ray tree).
const GLASS = [400, 200];
// The deepest the page traces (web/src/files.rs MAX_DEPTH: the browser's stack, not wasm's).
const MIRROR_DEPTH = +(process.env.RAYTREE_WEB_DEPTH ?? 512);

// --max-memory: so the CLI does not lower settings.max_rays to fit this machine's memory (the
// page, like the desktop inspector, traces at the scene's budget and echoes it in the tree).
const cli = (cmd, ...args) => execFileSync(bin, [cmd, '--max-memory', '65536', ...args], { cwd: root, maxBuffer: 1 << 28 });
const cliJson = (...args) => JSON.parse(cli(...args).toString());
const log = (...a) => console.log('web test:', ...a);

// Equal JSON, numbers to a relative 1e-12: wasm32's libm (Rust's port of musl) and glibc's
// round pow, exp, sin, ... differently in the last bit. Returns the numbers that differ and
// the largest relative difference; throws on any other difference.
const ulpStats = { count: 0, worst: 0 };
const close = (a, b, path = '$') => {
  if (typeof a === 'number' && typeof b === 'number') {
    if (a === b) return;
    const rel = Math.abs(a - b) / Math.max(Math.abs(a), Math.abs(b));
    if (!(rel <= 1e-12)) throw new Error(`${path}: ${a} != ${b} (relative ${rel})`);
    ulpStats.count += 1;
    ulpStats.worst = Math.max(ulpStats.worst, rel);
    return;
  }
  if (Array.isArray(a) || Array.isArray(b)) {
    if (!Array.isArray(a) || !Array.isArray(b) || a.length !== b.length) throw new Error(`${path}: ${JSON.stringify(a)?.slice(0, 80)} != ${JSON.stringify(b)?.slice(0, 80)}`);
    a.forEach((v, i) => close(v, b[i], `${path}[${i}]`));
    return;
  }
  if (a && b && typeof a === 'object' && typeof b === 'object') {
    const ka = Object.keys(a).sort(), kb = Object.keys(b).sort();
    assert.deepEqual(ka, kb, `${path}: keys`);
    ka.forEach((k) => close(a[k], b[k], `${path}.${k}`));
    return;
  }
  if (a !== b) throw new Error(`${path}: ${JSON.stringify(a)} != ${JSON.stringify(b)}`);
};
// SVG text equal but for its numbers, which are compared as above.
const closeSvg = (a, b) => {
  const num = /-?\d+(\.\d+)?(e-?\d+)?/g;
  assert.equal(a.replace(num, '#'), b.replace(num, '#'), 'the SVGs differ beyond their numbers');
  close(a.match(num).map(Number), b.match(num).map(Number), 'svg');
};

// A static server (as python3 -m http.server, with the wasm MIME type).
const types = { '.html': 'text/html', '.js': 'text/javascript', '.wasm': 'application/wasm' };
const server = createServer((req, res) => {
  let path = decodeURIComponent(new URL(req.url, 'http://x').pathname);
  if (path.endsWith('/')) path += 'index.html';
  try {
    const body = readFileSync(join(dist, path));
    res.writeHead(200, { 'content-type': types[extname(path)] ?? 'application/octet-stream' });
    res.end(body);
  } catch {
    res.writeHead(404).end();
  }
});
await new Promise((r) => server.listen(0, '127.0.0.1', r));
const base = `http://127.0.0.1:${server.address().port}/`;

const profile = mkdtempSync(join(tmpdir(), 'raytree-chromium-'));
const context = await chromium.launchPersistentContext(profile, {
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  headless: true,
  acceptDownloads: true,
  viewport: { width: 1560, height: 940 },
  args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
    '--disable-background-networking', '--disable-component-update', '--disable-sync'],
});
const failures = [];
try {
  const page = context.pages()[0] ?? (await context.newPage());
  page.on('pageerror', (e) => failures.push(`page error: ${e.message}`));
  page.on('console', (m) => { if (m.type() === 'error') log('console:', m.text()); });
  // The longest gap between animation frames: how long the page was frozen.
  await page.addInitScript(() => {
    window.__gap = { worst: 0, last: performance.now() };
    const tick = (t) => {
      window.__gap.worst = Math.max(window.__gap.worst, t - window.__gap.last);
      window.__gap.last = t;
      requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  });
  const state = () => page.evaluate(() => window.raytreeState && window.raytreeState());
  const waitFor = async (what, pred, ms = 120000) => {
    const t0 = Date.now();
    for (;;) {
      const s = await state();
      if (s && pred(s)) return s;
      if (Date.now() - t0 > ms) throw new Error(`timed out waiting for ${what}: ${JSON.stringify(s)}`);
      await page.waitForTimeout(25);
    }
  };
  const rendered = (scene) => (s) => s.rendered && s.scene === `fixtures/${scene}.json`;
  // Follow a link (the fragment) and wait for the render it starts (a newer generation).
  const setHash = async (hash, ms) => {
    const g = (await state()).generation;
    await page.evaluate((h) => { location.hash = h; }, `#${hash}`);
    return waitFor(hash, (s) => s.generation > g && s.rendered, ms);
  };
  const shot = async (name) => {
    await page.waitForTimeout(300);
    await page.screenshot({ path: join(out, `${name}.png`) });
  };
  const clickPixel = async ([x, y]) => {
    const p = await page.evaluate(([x, y]) => window.raytreePixelPosition(x, y), [x, y]);
    assert.ok(p, 'the image is on the canvas');
    // The browser reports whole CSS pixels: click the first whole coordinate inside the pixel.
    const inside = (c, z) => {
      const v = Math.ceil(c - z / 2 + 1e-3);
      assert.ok(v < c + z / 2, `pixel ${x},${y} is wider than a CSS pixel on the canvas (zoom ${z})`);
      return v;
    };
    await page.mouse.click(inside(p.x, p.zoom), inside(p.y, p.zoom));
    return waitFor(`the tree of ${x},${y}`, (s) => s.selection?.[0] === x && s.selection?.[1] === y && s.tree_nodes);
  };
  const tree = async () => JSON.parse(await page.evaluate(() => window.raytreeSelectedTree()));
  const download = async (kind) => {
    const [d] = await Promise.all([
      page.waitForEvent('download'),
      page.evaluate((k) => window.raytreeExport(k), kind),
    ]);
    const path = join(out, d.suggestedFilename());
    await d.saveAs(path);
    return { name: d.suggestedFilename(), bytes: readFileSync(path) };
  };
  const upload = async (files) => {
    await page.setInputFiles('#raytree-file', files);
  };

  // 1. Load, first image.
  const t0 = Date.now();
  await page.goto(`${base}#scene=classic`);
  let s = await waitFor('the first image', rendered('classic'));
  log(`classic: first image ${s.first_image_ms.toFixed(0)} ms after navigation start (${Date.now() - t0} ms here)`);
  await shot('classic');

  // 2. Click the glass ball: the CLI's tree.
  s = await clickPixel(GLASS);
  const got = await tree();
  const want = cliJson('trace', '--json', '--pixel', GLASS.join(','), 'fixtures/classic.json');
  close(got, want);
  assert.equal(got.nodes[0].hit?.object_name, 'glass ball', 'the camera ray hits the glass ball');
  assert.ok(got.nodes.some((n) => n.kind === 'refracted'), 'and refracts');
  log(`classic ${GLASS}: ${got.nodes.length} rays, equal to raytree trace --json`);
  await shot('classic-glass');

  // 3. Exports: tree JSON, diagram SVG, image PNG as the CLI writes them.
  const tj = await download('tree-json');
  assert.deepEqual(JSON.parse(tj.bytes.toString()), got, 'the tree JSON export is the tree shown');
  close(JSON.parse(tj.bytes.toString()), want);
  const svg = await download('diagram-svg');
  cli('diagram', 'fixtures/classic.json', '--pixel', GLASS.join(','), '-o', join(out, 'cli.svg'));
  closeSvg(svg.bytes.toString(), readFileSync(join(out, 'cli.svg')).toString());
  const png = await download('image-png');
  cli('render', 'fixtures/classic.json', '-o', join(out, 'cli.png'));
  assert.ok(png.bytes.equals(readFileSync(join(out, 'cli.png'))), 'image PNG export');
  log(`exports equal the CLI's: ${tj.name}, ${svg.name}, ${png.name}`);

  // 4. The path integrator through the URL fragment.
  s = await setHash(`scene=classic&pixel=${GLASS}&integrator=path&spp=4`);
  assert.equal(s.integrator, 'path');
  const pathWant = cliJson('trace', '--json', '--pixel', GLASS.join(','), '--integrator', 'path', '--spp', '4', 'fixtures/classic.json');
  close(await tree(), pathWant);
  const psvg = await download('diagram-svg');
  cli('diagram', 'fixtures/classic.json', '--pixel', GLASS.join(','), '--integrator', 'path', '--spp', '4', '-o', join(out, 'cli-path.svg'));
  closeSvg(psvg.bytes.toString(), readFileSync(join(out, 'cli-path.svg')).toString());
  log('path integrator: tree and diagram SVG equal the CLI\'s');
  await shot('classic-path');

  // 5. Time to image and the frame budget, scene by scene.
  const measures = [];
  // RAYTREE_WEB_MEASURE=0: classic only (the Cornell box takes minutes at 64 spp here).
  const scenes = process.env.RAYTREE_WEB_MEASURE === '0' ? ['classic'] : ['classic', 'cornell-box', 'caustic'];
  for (const scene of scenes) {
    // Start from another scene, so that each is opened afresh.
    const other = scene === 'diffuse' ? 'classic' : 'diffuse';
    await setHash(`scene=${other}`);
    await page.evaluate(() => { window.raytreeResetFrames(); window.__gap.worst = 0; window.__gap.last = performance.now(); });
    const start = Date.now();
    s = await setHash(`scene=${scene}`, 600000);
    const wall = Date.now() - start;
    const gap = await page.evaluate(() => window.__gap.worst);
    const m = { scene, size: `${s.width}x${s.height}`, spp: s.spp, integrator: s.integrator,
      image_ms: Math.round(s.image_ms), wall_ms: wall, worst_frame_ms: +s.worst_frame_ms.toFixed(1),
      worst_gap_ms: +gap.toFixed(1), slow: s.slow_frames };
    measures.push(m);
    log(JSON.stringify(m));
    await shot(scene);
  }

  // 5b. Background jobs step between frames: the comparison of two integrators, the split by
  // strategy, the denoiser and the acne lab run a pixel at a time, so no frame waits for a
  // whole render.
  for (const [job, hash, done] of [
    ['versus', 'scene=caustic&integrator=path&spp=8', (s) => s.versus.summary && !s.versus.running],
    ['strategies', 'scene=caustic&integrator=bdpt&spp=2', (s) => s.strategies.captions.length > 0 && !s.strategies.running],
    ['denoise', 'scene=caustic&integrator=path&spp=8', (s) => s.denoise?.startsWith('Ready')],
    ['acne', 'scene=classic&integrator=whitted&spp=1', (s) => s.lab.started && s.lab.done],
  ]) {
    await setHash('scene=diffuse');
    s = await setHash(hash, 600000);
    await page.evaluate((job) => { window.raytreeResetFrames(); window.__gap.worst = 0; window.__gap.last = performance.now(); window.raytreeStart(job); }, job);
    const start = Date.now();
    s = await waitFor(`the ${job} job`, done, 600000);
    const wall = Date.now() - start;
    const gap = await page.evaluate(() => window.__gap.worst);
    const m = { job, scene: hash, wall_ms: wall, worst_frame_ms: +s.worst_frame_ms.toFixed(1),
      worst_gap_ms: +gap.toFixed(1), slow: s.slow_frames };
    measures.push(m);
    log(JSON.stringify(m));
    // Whole in one frame, the job would freeze the page for all of its time.
    assert.ok(gap < wall / 4, `${job}: the page froze for ${gap} ms of the job's ${wall} ms`);
    if (job === 'versus') assert.match(s.versus.summary, /Whitted luminance/);
    if (job === 'acne') assert.ok(s.lab.cells > 1, JSON.stringify(s.lab));
    await shot(`job-${job}`);
  }
  writeFileSync(join(out, 'measurements.json'), JSON.stringify(measures, null, 2));

  // 6. Hostile input: the page says why and goes on.
  const big = join(out, 'big.json');
  execFileSync('truncate', ['-s', '100M', big]);
  await upload(big);
  s = await waitFor('the 100 MB refusal', (s) => s.message?.includes('larger than the limit'));
  rmSync(big);
  await upload({ name: 'photo.json', mimeType: 'application/json', buffer: Buffer.from([0x89, 0x50, 0x4e, 0x47, 0xff, 0xfe, 0]) });
  s = await waitFor('the binary refusal', (s) => s.message?.includes('not UTF-8'));
  const huge = JSON.parse(readFileSync(join(root, 'fixtures/classic.json')));
  huge.camera.width = 65536;
  huge.camera.height = 65536;
  await upload({ name: 'huge.json', mimeType: 'application/json', buffer: Buffer.from(JSON.stringify(huge)) });
  s = await waitFor('the 65536x65536 refusal', (s) => s.error?.includes('65536x65536'));
  await upload({ name: 'broken.json', mimeType: 'application/json', buffer: Buffer.from('{\n  "camera": [1,\n') });
  s = await waitFor('the syntax error', (s) => /broken\.json:\d+:\d+/.test(s.error ?? ''));
  log(`hostile input refused: ${s.error.split('\n')[0]}`);
  await shot('hostile');
  // Still working: the classic scene renders and traces.
  await setHash('scene=diffuse');
  await setHash('scene=classic&integrator=whitted&spp=1');
  await clickPixel(GLASS);
  close(await tree(), want);

  // 7. Deep recursion: two facing perfect mirrors at the page's deepest max_depth; deeper is
  // refused with a message.
  const mirrors = {
    camera: { position: [0, 0, 0], look_at: [0, 0, -1], up: [0, 1, 0], fov_y: 10, width: 16, height: 16 },
    background: [0.2, 0.3, 0.4],
    materials: { m: { diffuse: [0, 0, 0], reflectivity: [1, 1, 1] } },
    objects: [
      { type: 'plane', point: [0, 0, -1], normal: [0, 0, 1], material: 'm' },
      { type: 'plane', point: [0, 0, 1], normal: [0, 0, -1], material: 'm' },
    ],
    lights: [],
    settings: { max_depth: MIRROR_DEPTH, min_weight: 0, spp: 1 },
  };
  writeFileSync(join(out, 'mirrors-deep.json'), JSON.stringify({ ...mirrors, settings: { ...mirrors.settings, max_depth: 2 * MIRROR_DEPTH } }));
  await upload(join(out, 'mirrors-deep.json'));
  s = await waitFor('the refusal of a deeper recursion', (s) => s.error?.includes('deeper than the web page traces'));
  writeFileSync(join(out, 'mirrors-deep.json'), JSON.stringify(mirrors));
  await upload(join(out, 'mirrors-deep.json'));
  await waitFor('the deep mirrors', (s) => s.rendered && s.scene === 'uploads/mirrors-deep.json');
  s = await clickPixel([8, 8]);
  const deep = await tree();
  log(`deep tree in the page: ${deep.nodes.length} rays, to depth ${Math.max(...deep.nodes.map((n) => n.depth))}, max_rays ${deep.settings.max_rays}`);
  close(deep, cliJson('trace', '--json', '--pixel', '8,8', join(out, 'mirrors-deep.json')));
  const depth = Math.max(...deep.nodes.map((n) => n.depth ?? 0));
  assert.equal(depth, MIRROR_DEPTH, 'the recursion reaches max_depth');
  log(`deep recursion: ${deep.nodes.length} rays to depth ${depth}, equal to the CLI's`);

  // 8. pbrt-v4 and Mitsuba 3 scenes opened with their companions, selected together (the
  // browser gives no folders: a pbrt scene's `geometry/panel.ply` is found by its name): the
  // CLI's tree from the same files.
  const formats = join(out, 'formats');
  mkdirSync(join(formats, 'geometry'), { recursive: true });
  const fixtureText = (f) => readFileSync(join(root, 'fixtures/formats', f)).toString();
  const pbrt = fixtureText('cornell-box.pbrt')
    .replace('"integer xresolution" 256 "integer yresolution" 256', '"integer xresolution" 32 "integer yresolution" 32')
    .replace('"integer pixelsamples" 64', '"integer pixelsamples" 4')
    + '\nAttributeBegin\nMaterial "diffuse" "rgb reflectance" [0.2 0.3 0.9]\nShape "plymesh" "string filename" "geometry/panel.ply"\nAttributeEnd\n';
  writeFileSync(join(formats, 'scene.pbrt'), pbrt);
  writeFileSync(join(formats, 'box-tall.pbrt'), fixtureText('box-tall.pbrt'));
  // A binary PLY: a quad (two triangles) in front of the back wall.
  const header = 'ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n';
  const body = Buffer.alloc(4 * 12 + 2 * 13);
  [[-0.9, 1.1, -0.6], [-0.3, 1.1, -0.6], [-0.3, 1.7, -0.6], [-0.9, 1.7, -0.6]].flat().forEach((v, i) => body.writeFloatLE(v, 4 * i));
  [[0, 1, 2], [0, 2, 3]].forEach((f, i) => {
    body.writeUInt8(3, 48 + 13 * i);
    f.forEach((v, j) => body.writeInt32LE(v, 48 + 13 * i + 1 + 4 * j));
  });
  writeFileSync(join(formats, 'geometry', 'panel.ply'), Buffer.concat([Buffer.from(header), body]));
  await upload([join(formats, 'box-tall.pbrt'), join(formats, 'geometry', 'panel.ply'), join(formats, 'scene.pbrt')]);
  await waitFor('the pbrt scene', (s) => s.rendered && s.scene === 'uploads/scene.pbrt');
  for (const px of [[12, 14], [20, 24]]) {
    await clickPixel(px);
    close(await tree(), cliJson('trace', '--json', '--pixel', px.join(','), join(formats, 'scene.pbrt')));
  }
  await shot('pbrt-upload');
  const xml = fixtureText('cornell-box.xml')
    .replace('<default name="spp" value="64"/>', '<default name="spp" value="4"/>')
    .replace('<integer name="width" value="256"/>', '<integer name="width" value="32"/>')
    .replace('<integer name="height" value="256"/>', '<integer name="height" value="32"/>');
  writeFileSync(join(formats, 'scene.xml'), xml);
  for (const f of ['box-tall.obj', 'box-short.obj']) writeFileSync(join(formats, f), fixtureText(f));
  await upload([join(formats, 'box-short.obj'), join(formats, 'scene.xml'), join(formats, 'box-tall.obj')]);
  await waitFor('the Mitsuba scene', (s) => s.rendered && s.scene === 'uploads/scene.xml');
  await clickPixel([16, 20]);
  close(await tree(), cliJson('trace', '--json', '--pixel', '16,20', join(formats, 'scene.xml')));
  // A pbrt scene whose mesh was not selected with it (nor before): named, the page goes on.
  writeFileSync(join(formats, 'lost.pbrt'), pbrt.replace('geometry/panel.ply', 'geometry/lost.ply'));
  await upload([join(formats, 'lost.pbrt')]);
  s = await waitFor('the missing companion', (s) => s.error?.includes('lost.ply'));
  assert.equal(s.scene, 'uploads/scene.xml', 'the page keeps the scene it had');
  log(`pbrt and Mitsuba uploads with companions: trees equal the CLI's; a missing one: ${s.error.split('\n')[0]}`);
  log(`numbers that differ from the CLI's in the last bits: ${ulpStats.count}, largest relative difference ${ulpStats.worst.toExponential(2)}`);
} catch (e) {
  failures.push(e.stack ?? String(e));
} finally {
  await context.close();
  server.close();
  rmSync(profile, { recursive: true, force: true });
}
if (failures.length) {
  console.error(failures.join('\n'));
  process.exit(1);
}
log('passed');
