// Browser test of the animation page: runs a scene with the `lagrangian`
// command, opens the animation.html it wrote in headless Chromium (Debian's
// chromium, driven by playwright-core) with every non-file request blocked,
// and checks that
//  - the page loads and reports no JavaScript error and makes no network request;
//  - at several sample times, each body is drawn where trajectory.csv says:
//    the body centres computed here from the CSV (for built-in models by this
//    file's own formulas from the generalized coordinates) and projected with
//    the page's camera land within 1.5 px of the centres the page drew, and
//    the pixel there has the body's colour (or, for a gas, is not background);
//  - playing advances time, and an event flashes when playback passes it.
// Usage: node check_page.mjs LAGRANGIAN SCENE.toml OUT_DIR CASE [SCREENSHOT.png]
// CASE names the expected-position rule (see `cases` below).

import { execFileSync } from 'node:child_process';
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import assert from 'node:assert/strict';
// playwright-core from web/node_modules (scripts/setup installs it with the tests)
const { chromium } = await import(new URL('../../web/node_modules/playwright-core/index.mjs', import.meta.url));

const [cli, sceneFile, outDir, caseName, screenshot] = process.argv.slice(2);
if (!caseName) throw new Error('usage: node check_page.mjs LAGRANGIAN SCENE.toml OUT_DIR CASE [SCREENSHOT.png]');

// -- expected body centres (m) from one trajectory.csv row ----------------------------

const col = (row, header, name) => {
  const k = header.indexOf(name);
  assert.ok(k >= 0, `trajectory.csv has no column '${name}' (header: ${header.slice(0, 12).join(',')}…)`);
  return row[k];
};
// Particle scenes: each body's x, y, z columns, by the names the page shows.
const particles = (row, header, bodies) =>
  bodies.map((b) => ['x', 'y', 'z'].map((a) => col(row, header, `${b.name}.${a}`)));

const cases = {
  particles,
  gas: particles,
  // Double pendulum (examples/scenes/double_pendulum.toml: l1 = l2 = 1 m):
  // pivot at the origin, angles from the downward vertical, y up, z = 0.
  double_pendulum: (row, header) => {
    const t1 = col(row, header, 'theta1'), t2 = col(row, header, 'theta2');
    const x1 = Math.sin(t1), y1 = -Math.cos(t1);
    return [[x1, y1, 0], [x1 + Math.sin(t2), y1 - Math.cos(t2), 0]];
  },
  // Two bodies in the plane, Cartesian coordinates of each.
  two_body: (row, header) => [
    [col(row, header, 'x1'), col(row, header, 'y1'), 0],
    [col(row, header, 'x2'), col(row, header, 'y2'), 0],
  ],
  // Oblique impact of two spheres in the plane, likewise.
  oblique_impact: (row, header) => [
    [col(row, header, 'x1'), col(row, header, 'y1'), 0],
    [col(row, header, 'x2'), col(row, header, 'y2'), 0],
  ],
};
const expected = cases[caseName];
assert.ok(expected, `unknown case '${caseName}'`);

// -- the run -----------------------------------------------------------------------------

execFileSync(cli, ['run', sceneFile, '--out', outDir, '--no-plots', '-q'], { stdio: 'inherit' });
const page_path = join(outDir, 'animation.html');
const csv = readFileSync(join(outDir, 'trajectory.csv'), 'utf8').trim().split('\n');
const header = csv[0].split(',');
const rows = csv.slice(1).filter((l) => l && l[0] !== '#').map((l) => l.split(',').map(Number));
const rowAt = (t) => {
  let best = rows[0];
  for (const r of rows) if (Math.abs(r[0] - t) < Math.abs(best[0] - t)) best = r;
  assert.ok(Math.abs(best[0] - t) <= 1e-12 * Math.max(1, Math.abs(t)), `no trajectory row at the page's sample t = ${t}`);
  return best;
};

// -- the browser ----------------------------------------------------------------------------

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
         '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run'],
});
let failed = false;
try {
  const context = await browser.newContext({ viewport: { width: 1200, height: 700 }, offline: true });
  const requests = [];
  await context.route('**/*', (route) => {
    const url = route.request().url();
    if (url.startsWith('file://')) return route.continue();
    requests.push(url);
    return route.abort();
  });
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('console', (m) => { if (m.type() === 'error') errors.push(m.text()); });
  await page.goto('file://' + page_path);
  await page.waitForFunction(() => window.lagrangian && window.lagrangian.ready, null, { timeout: 30000 });

  const info = await page.evaluate(() => ({
    bodies: window.lagrangian.data.bodies, times: window.lagrangian.data.frames.t,
    events: window.lagrangian.data.events,
  }));
  assert.ok(info.bodies.length > 0, 'the page draws no body');
  const n = info.times.length;
  const picks = [...new Set([0, 0.13, 0.37, 0.61, 0.89, 1].map((u) => Math.round(u * (n - 1))))];
  let checked = 0, worst = 0;
  for (const k of picks) {
    const t = info.times[k];
    const s = await page.evaluate((tt) => { window.lagrangian.seek(tt); return window.lagrangian.state(); }, t);
    assert.equal(s.t, t);
    const want = expected(rowAt(t), header, info.bodies);
    assert.equal(want.length, info.bodies.length, 'bodies drawn vs bodies expected');
    const m = s.viewProjection;  // column-major 4x4
    for (let b = 0; b < want.length; ++b) {
      const [x, y, z] = want[b];
      const cx = m[0] * x + m[4] * y + m[8] * z + m[12], cy = m[1] * x + m[5] * y + m[9] * z + m[13];
      const cw = m[3] * x + m[7] * y + m[11] * z + m[15];
      const px = ((cx / cw + 1) / 2) * s.width, py = ((1 - cy / cw) / 2) * s.height;
      const d = Math.hypot(px - s.bodies[b].x, py - s.bodies[b].y);
      worst = Math.max(worst, d);
      assert.ok(d <= 1.5, `t = ${t}: body '${info.bodies[b].name}' drawn at (${s.bodies[b].x.toFixed(1)}, ` +
                          `${s.bodies[b].y.toFixed(1)}) px, the CSV puts it at (${px.toFixed(1)}, ${py.toFixed(1)})`);
      if (px < 2 || py < 2 || px > s.width - 2 || py > s.height - 2) continue;  // off screen: nothing to see
      if (caseName === 'gas' && b % 50 !== 0) continue;
      const rgb = await page.evaluate(([xx, yy]) => window.lagrangian.pixel(xx, yy), [px, py]);
      const bg = [0xf4, 0xf4, 0xf0];
      const dist = (a, c) => Math.hypot(a[0] - c[0], a[1] - c[1], a[2] - c[2]);
      if (caseName === 'gas') {
        assert.ok(dist(rgb, bg) > 40, `t = ${t}: nothing drawn at body '${info.bodies[b].name}' (pixel ${rgb})`);
      } else {
        const own = await page.evaluate((bb) => window.lagrangian.bodyColor(bb), b);
        // the nearest body colour wins where spheres overlap (Newton's cradle): accept any body's colour there
        const colours = await page.evaluate((nb) => [...Array(nb).keys()].map((i) => window.lagrangian.bodyColor(i)),
                                            info.bodies.length);
        const near = Math.min(...colours.map((c) => dist(rgb, c)));
        assert.ok(dist(rgb, own) < 60 || near < 60,
                  `t = ${t}: the pixel at body '${info.bodies[b].name}' is ${rgb}, not its colour ${own}`);
      }
      ++checked;
    }
  }
  assert.ok(checked > 0, 'no body was on screen at the sampled times');

  // Playing advances time.
  await page.evaluate(() => { window.lagrangian.seek(window.lagrangian.data.frames.t[0]); window.lagrangian.play(true); });
  await page.waitForFunction(() => window.lagrangian.state().frame > 0, null, { timeout: 20000 });
  await page.evaluate(() => window.lagrangian.play(false));
  // An event flashes when playback passes it.
  if (info.events.length > 0) {
    const e = info.events[Math.floor(info.events.length / 2)];
    await page.evaluate((te) => {
      const times = window.lagrangian.data.frames.t;
      let k = 0;
      while (k + 1 < times.length && times[k + 1] < te) ++k;
      window.lagrangian.seek(times[Math.max(0, k - 1)]);
      window.lagrangian.play(true);
    }, e.t);
    await page.waitForFunction(() => document.getElementById('flash').classList.contains('on'), null, { timeout: 30000 });
    await page.evaluate(() => window.lagrangian.play(false));
  }
  if (screenshot) {
    await page.evaluate((t) => { window.lagrangian.seek(t); document.getElementById('flash').classList.remove('on'); },
                        info.times[picks[2]]);
    await page.screenshot({ path: screenshot });
  }
  const pageErrors = await page.evaluate(() => window.lagrangian.errors);
  assert.deepEqual(errors.concat(pageErrors), [], 'JavaScript errors');
  assert.deepEqual(requests, [], 'network requests');
  console.log(`${caseName}: ${info.bodies.length} bodies, ${n} samples; ${checked} body positions checked at ` +
              `${picks.length} times, worst ${worst.toFixed(2)} px; ${info.events.length} events; no errors, no requests`);
} catch (e) {
  failed = true;
  console.error(e);
} finally {
  await browser.close();
}
process.exit(failed ? 1 : 0);
