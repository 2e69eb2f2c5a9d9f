// Opens a tiltfield report.html in headless Chromium (Debian's /usr/bin/chromium driven by
// playwright-core) and checks that it rendered: every plot has drawn lines or says it has no data, at
// least MIN_PLOTS plots have lines, the hover read-out works, the 3-D view's WebGL canvas has drawn
// pixels, nothing was fetched from outside the file, and the console has no errors. Saves a screenshot.
// With --expect-stock: a machined stock layer is there, renders under each of its colourings, and hovering
// it reads out its deviation or the block that cut it.
//
//   node tests/report/check_report.mjs REPORT.html SCREENSHOT.png [--min-plots=N] [--full-page] [--expect-stock]
//
// Exit 0 when every check passes, 1 when one fails (each failure printed), 2 on bad usage or when the
// browser cannot start. Environment: TILTFIELD_NODE_MODULES (the build's report_npm/node_modules, where
// playwright-core is; default build/report_npm/node_modules), CHROMIUM (default /usr/bin/chromium).
import { createRequire } from 'node:module';
import { mkdtempSync, rmSync, existsSync } from 'node:fs';
import { tmpdir } from 'node:os';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const args = process.argv.slice(2);
const positional = args.filter((a) => !a.startsWith('--'));
const option = (name, fallback) => {
  const a = args.find((x) => x.startsWith(`--${name}=`));
  return a ? a.slice(name.length + 3) : fallback;
};
if (positional.length !== 2) {
  console.error('usage: node check_report.mjs REPORT.html SCREENSHOT.png [--min-plots=N] [--full-page] [--expect-stock]');
  process.exit(2);
}
const [htmlFile, pngFile] = positional.map((p) => path.resolve(p));
const minPlots = Number(option('min-plots', '1'));
const here = path.dirname(fileURLToPath(import.meta.url));
const nodeModules = process.env.TILTFIELD_NODE_MODULES || path.join(here, '..', '..', 'build', 'report_npm', 'node_modules');
const executablePath = process.env.CHROMIUM || '/usr/bin/chromium';
if (!existsSync(htmlFile)) {
  console.error(`check_report: ${htmlFile}: no such file`);
  process.exit(2);
}
if (!existsSync(executablePath)) {
  console.error(`check_report: ${executablePath} not found (Debian: apt-get install chromium chromium-driver)`);
  process.exit(2);
}
const require = createRequire(path.join(nodeModules, 'noop.js'));
const { chromium } = require('playwright-core');

const failures = [];
const fail = (what) => failures.push(what);
const userDataDir = mkdtempSync(path.join(tmpdir(), 'tiltfield-chromium-'));
let context;
try {
  context = await chromium.launchPersistentContext(userDataDir, {
    executablePath,
    headless: true,
    viewport: { width: 1400, height: 900 },
    deviceScaleFactor: 1,
    args: [
      '--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync',
      // WebGL without a GPU: ANGLE on SwiftShader (recent Chromium needs the explicit opt-in).
      '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
    ],
  });
} catch (e) {
  console.error(`check_report: cannot start ${executablePath}: ${e.message}`);
  rmSync(userDataDir, { recursive: true, force: true });
  process.exit(2);
}

try {
  const page = context.pages()[0] || (await context.newPage());
  page.on('console', (m) => { if (m.type() === 'error') fail(`console error: ${m.text()}`); });
  page.on('pageerror', (e) => fail(`page error: ${e.message}`));
  // The report must be self-contained: any request other than the file itself is a failure.
  const url = pathToFileURL(htmlFile).href;
  await page.route('**/*', (route) => {
    const u = route.request().url();
    if (u === url || u.startsWith('data:') || u.startsWith('blob:')) return route.continue();
    fail(`external request: ${u}`);
    return route.abort();
  });
  await page.goto(url, { waitUntil: 'load' });
  await page.waitForFunction(() => document.body.dataset.viewer, null, { timeout: 60000 }).catch(() => {});
  const viewer = await page.evaluate(() => document.body.dataset.viewer || 'missing');
  if (viewer !== 'ready') fail(`3-D view not ready: state '${viewer}'`);

  const plots = await page.evaluate(() => [...document.querySelectorAll('svg.plot')].map((svg) => ({
    id: svg.id,
    paths: [...svg.querySelectorAll('path.series')].filter((p) => (p.getAttribute('d') || '').length > 10).length,
    empty: !!svg.querySelector('text.empty'),
    width: svg.getBoundingClientRect().width,
  })));
  let drawn = 0;
  for (const p of plots) {
    if (p.paths > 0) ++drawn;
    else if (!p.empty) fail(`plot ${p.id} has neither lines nor a "no data" note`);
    if (p.width < 100) fail(`plot ${p.id} is not laid out (width ${p.width})`);
  }
  if (drawn < minPlots) fail(`${drawn} plots have lines, expected at least ${minPlots}`);

  // Hover read-out on the first plot with lines.
  const first = plots.find((p) => p.paths > 0);
  if (first) {
    await page.locator(`#${first.id}`).scrollIntoViewIfNeeded();
    const box = await page.locator(`#${first.id}`).boundingBox();
    await page.mouse.move(box.x + box.width * 0.55, box.y + box.height * 0.5);
    const text = await page.locator(`#${first.id} ~ .plot-cursor`).textContent().catch(() => '');
    if (!/\d/.test(text || '')) fail(`hover read-out on ${first.id} shows no value ('${text}')`);
    await page.mouse.move(0, 0);
    await page.evaluate(() => window.scrollTo(0, 0));
  }

  // Drawn pixels and distinct colours of the 3-D view's canvas after a fresh render.
  const canvasStats = () => page.evaluate(() => {
      window.tfViewer.render();
      const src = document.querySelector('#tf-viewer canvas');
      const c = document.createElement('canvas');
      c.width = src.width;
      c.height = src.height;
      const g = c.getContext('2d');
      g.drawImage(src, 0, 0);
      const d = g.getImageData(0, 0, c.width, c.height).data;
      let n = 0;
      const colours = new Set();
      for (let i = 0; i < d.length; i += 4)
        if (d[i + 3] > 0) {
          ++n;
          colours.add((d[i] >> 3) * 1024 + (d[i + 1] >> 3) * 32 + (d[i + 2] >> 3));
        }
      return { drawn: n, total: d.length / 4, colours: colours.size };
    });
  const checkCanvas = (pixels, what) => {
    if (pixels.drawn < 0.02 * pixels.total) fail(`3-D canvas${what}: only ${pixels.drawn} of ${pixels.total} pixels drawn`);
    if (pixels.colours < 16) fail(`3-D canvas${what}: only ${pixels.colours} distinct colours (no shading?)`);
  };
  let pixels = { drawn: 0, total: 0, colours: 0 };
  let stock = null;
  if (viewer === 'ready') {
    pixels = await canvasStats();
    checkCanvas(pixels, '');
    if (args.includes('--expect-stock')) {
      // The machined stock is there: every colouring renders, and hovering the stock reads it out.
      stock = { colorings: await page.evaluate(() => window.tfViewer.colorings.stock || []), readout: '' };
      if (!stock.colorings.length) fail('no machined stock layer with colourings');
      for (const id of stock.colorings) {
        if (!(await page.evaluate((c) => window.tfViewer.setColoring('stock', c), id))) fail(`colouring '${id}' not applied`);
        checkCanvas(await canvasStats(), ` coloured by ${id}`);
      }
      if (stock.colorings.length) await page.evaluate((c) => window.tfViewer.setColoring('stock', c), stock.colorings[0]);
      stock.readout = await page.evaluate(() => {
        const r = document.querySelector('#tf-viewer canvas').getBoundingClientRect();
        for (let gy = 1; gy < 12; ++gy)
          for (let gx = 1; gx < 12; ++gx) {
            const t = window.tfViewer.readoutAt(r.left + (r.width * gx) / 12, r.top + (r.height * gy) / 12);
            if (t && /block|raw stock|deviation/.test(t)) return t;
          }
        return '';
      });
      if (!stock.readout) fail('hovering the stock reads out nothing');
      await page.evaluate(() => { document.querySelector('.viewer-tip').style.display = 'none'; });
    }
  }
  await page.screenshot({ path: pngFile, fullPage: args.includes('--full-page') });
  console.log(JSON.stringify({ viewer, plots: plots.length, plots_drawn: drawn, canvas: pixels,
                               ...(stock ? { colorings: stock.colorings, readout: stock.readout } : {}),
                               failures: failures.length }));
} finally {
  await context.close();
  rmSync(userDataDir, { recursive: true, force: true });
}
for (const f of failures) console.error(`check_report: ${f}`);
process.exit(failures.length ? 1 : 0);
