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

// The column headed "<name> [<unit>]": a length must be in m, an angle in rad.
const col = (row, header, name, unit = 'm') => {
  const field = `${name} [${unit}]`;
  const k = header.indexOf(field);
  assert.ok(k >= 0, `trajectory.csv has no column '${field}' (header: ${header.slice(0, 12).join(',')}…)`);
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
    const t1 = col(row, header, 'theta1', 'rad'), t2 = col(row, header, 'theta2', 'rad');
    const x1 = Math.sin(t1), y1 = -Math.cos(t1);
    return [[x1, y1, 0], [x1 + Math.sin(t2), y1 - Math.cos(t2), 0]];
  },
  // The spherical pendulum stated by expressions
  // (examples/scenes/text/spherical_pendulum.toml: l = 1 m), bob at
  // (sin θ cos φ, sin θ sin φ, −cos θ) from the pivot at the origin, z up.
  spherical_text: (row, header) => {
    const th = col(row, header, 'theta', 'rad'), ph = col(row, header, 'phi', 'rad');
    return [[Math.sin(th) * Math.cos(ph), Math.sin(th) * Math.sin(ph), -Math.cos(th)]];
  },
  // A particle stated by expressions at (x, y) in the vertical plane
  // (examples/scenes/text/projectile_on_incline.toml: its point is x = "x",
  // y = "y"), bouncing on the incline: the page flashes its impacts and rest.
  text_plane_point: (row, header) => [[col(row, header, 'x'), col(row, header, 'y'), 0]],
  // Two bodies in the plane, Cartesian coordinates of each.
  two_body: (row, header) => [
    [col(row, header, 'x1'), col(row, header, 'y1'), 0],
    [col(row, header, 'x2'), col(row, header, 'y2'), 0],
  ],
  // Atwood machine (examples/scenes/atwood_machine.toml: c = 0, d = 1 m): the masses hang at x = ∓0.1 m (the
  // pulley's radius) at heights y1, y2, never above the pulley's axle at c/2 + d = 1 m.
  atwood: (row, header) => {
    const y1 = col(row, header, 'y1'), y2 = col(row, header, 'y2');
    assert.ok(y1 <= 1 + 1e-9 && y2 <= 1 + 1e-9, `a mass above the pulley: y1 = ${y1}, y2 = ${y2}`);
    return [[-0.1, y1, 0], [0.1, y2, 0]];
  },
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
    boxes: window.lagrangian.data.boxes.length,
    events: window.lagrangian.data.events,
  }));
  assert.ok(info.bodies.length > 0, 'the page draws no body');
  const n = info.times.length;
  const picks = [...new Set([0, 0.13, 0.37, 0.61, 0.89, 1].map((u) => Math.round(u * (n - 1))))];
  let checked = 0, plain = 0, worst = 0;
  for (const k of picks) {
    const t = info.times[k];
    const s = await page.evaluate((tt) => { window.lagrangian.seek(tt); return window.lagrangian.state(); }, t);
    assert.equal(s.t, t);
    const want = expected(rowAt(t), header, info.bodies);
    assert.equal(want.length, info.bodies.length, 'bodies drawn vs bodies expected');
    const m = s.viewProjection;  // column-major 4x4
    const project = ([x, y, z]) => {
      const cx = m[0] * x + m[4] * y + m[8] * z + m[12], cy = m[1] * x + m[5] * y + m[9] * z + m[13];
      const cw = m[3] * x + m[7] * y + m[11] * z + m[15];
      return [((cx / cw + 1) / 2) * s.width, ((1 - cy / cw) / 2) * s.height, cw];  // cw: depth
    };
    // Where the CSV puts each body on the screen, and how big it is drawn
    // there (its radius, or the page's 2.5 % of the scene for a point mass,
    // projected along the axes, widened to bound the disc's radius).
    const drawnRadius = await page.evaluate(() => window.lagrangian.state().pointRadius);
    const screen = want.map((p, b) => {
      const r = info.bodies[b].radius > 0 ? info.bodies[b].radius : drawnRadius;
      const c = project(p);
      let rp = 0;
      for (let a = 0; a < 3; ++a) {
        const q = p.slice();
        q[a] += r;
        const d = project(q);
        rp = Math.max(rp, Math.hypot(d[0] - c[0], d[1] - c[1]));
      }
      // along an axis the offset shows at least √(2/3) of the disc's radius
      return { x: c[0], y: c[1], depth: c[2], r: 1.25 * rp + 1 };
    });
    const bg = [0xf4, 0xf4, 0xf0];
    const dist = (a, c) => Math.hypot(a[0] - c[0], a[1] - c[1], a[2] - c[2]);
    const colours = await page.evaluate((nb) => [...Array(nb).keys()].map((i) => window.lagrangian.bodyColor(i)),
                                        info.bodies.length);
    // Positions: every body. Pixels: every body, or for a gas those in plain
    // view (up to 60 a time), all read in one call.
    const probed = [];
    for (let b = 0; b < want.length; ++b) {
      const { x: px, y: py } = screen[b];
      const d = Math.hypot(px - s.bodies[b].x, py - s.bodies[b].y);
      worst = Math.max(worst, d);
      assert.ok(d <= 1.5, `t = ${t}: body '${info.bodies[b].name}' drawn at (${s.bodies[b].x.toFixed(1)}, ` +
                          `${s.bodies[b].y.toFixed(1)}) px, the CSV puts it at (${px.toFixed(1)}, ${py.toFixed(1)})`);
      if (px < 2 || py < 2 || px > s.width - 2 || py > s.height - 2) continue;  // off screen: nothing to see
      // The bodies nearer the camera whose discs cover this centre may hide it.
      const covering = [];
      for (let o = 0; o < want.length; ++o)
        if (o !== b && screen[o].depth < screen[b].depth &&
            Math.hypot(screen[o].x - px, screen[o].y - py) < screen[o].r + 1) covering.push(o);
      if (caseName === 'gas' && (covering.length > 0 || probed.length >= 60)) continue;
      // The centre and four points a third of the radius around it: most of
      // them show the body (a line in front, a box edge, may cross one).
      const r3 = screen[b].r / 3;
      probed.push({ b, covering, points: [[px, py], [px - r3, py], [px + r3, py], [px, py - r3], [px, py + r3]] });
    }
    const flat = await page.evaluate((pts) => window.lagrangian.pixels(pts), probed.flatMap((p) => p.points));
    const pixels = probed.map((_, i) => flat.slice(5 * i, 5 * i + 5));
    probed.forEach(({ b, covering }, i) => {
      const probes = pixels[i];
      const votes = (c) => probes.filter((q) => dist(q, c) < 60).length;
      if (info.boxes > 0 && votes([0x44, 0x44, 0x44]) >= 3 && votes(colours[b]) < 3) return;  // behind a box edge
      const own = votes(colours[b]) >= 3;
      const hidden = covering.some((o) => votes(colours[o]) >= 3);
      assert.ok(own || hidden, `t = ${t}: the pixel at body '${info.bodies[b].name}' is ${probes[0]}, not its colour ` +
                               `${colours[b]}` + (covering.length ? ' nor that of a body in front of it' : ''));
      assert.ok(probes.filter((q) => dist(q, bg) > 40).length >= 3, `t = ${t}: nothing drawn at body '${info.bodies[b].name}'`);
      ++checked;
      if (own && covering.length === 0) ++plain;
    });
  }
  assert.ok(checked > 0, 'no body was on screen at the sampled times');
  // Most bodies are seen in their own colour, in plain view (the gas: dozens).
  assert.ok(plain >= Math.min(10, picks.length * info.bodies.length) / 2, `only ${plain} bodies seen in plain view`);

  // The energy chart shows the relative change (E − E0)/|E0| of trajectory.csv's energy column (of the run's
  // energy scale, report.json's, when E0 = 0) on an axis at least ±1e-10 wide: round-off is not drawn at full
  // height, and the title says "constant to" exactly when the change stays below that floor.
  {
    const k = header.findIndex((h) => h.startsWith('energy ['));
    assert.ok(k >= 0, 'trajectory.csv has no energy column');
    const E = rows.map((r) => r[k]).filter(Number.isFinite);
    const scale = JSON.parse(readFileSync(join(outDir, 'report.json'), 'utf8')).report.energy_scale;
    const ref = E[0] !== 0 ? Math.abs(E[0]) : scale;
    const rel = E.map((v) => (v - E[0]) / ref);
    const span = Math.max(...rel.map(Math.abs)), floor = 1e-10;
    const charts = await page.evaluate(() => window.lagrangian.charts());
    const chart = charts[0];
    assert.ok(chart.title.includes('E0') || chart.title.includes('constant to'), `energy chart title '${chart.title}'`);
    assert.equal(chart.title.includes('constant to'), span <= floor,
                 `energy chart title '${chart.title}' for a relative change of ${span}`);
    const lo = Math.min(-floor, ...rel), hi = Math.max(floor, ...rel);
    const near = (a, b) => Math.abs(a - b) <= 1e-8 * Math.max(Math.abs(b), floor);
    assert.ok(near(chart.ymin, lo) && near(chart.ymax, hi),
              `energy axis [${chart.ymin}, ${chart.ymax}], the CSV's relative change spans [${lo}, ${hi}]`);
  }

  // Playing advances time.
  await page.evaluate(() => { window.lagrangian.seek(window.lagrangian.data.frames.t[0]); window.lagrangian.play(true); });
  await page.waitForFunction(() => window.lagrangian.state().frame > 0, null, { timeout: 20000 });
  await page.evaluate(() => window.lagrangian.play(false));
  // An event flashes when playback passes it.
  if (info.events.length > 0) {
    const e = info.events[Math.floor(info.events.length / 2)];
    await page.evaluate((te) => {
      const flash = document.getElementById('flash');  // no banner left from the playback above
      flash.classList.remove('on');
      flash.textContent = '';
      const times = window.lagrangian.data.frames.t;
      let k = 0;
      while (k + 1 < times.length && times[k + 1] < te) ++k;
      window.lagrangian.seek(times[Math.max(0, k - 1)]);
      window.lagrangian.play(true);
    }, e.t);
    // A banner names an event of the frame that passed it: its kind, what it
    // names and its time, within two frames of the event's.
    await page.waitForFunction(() => document.getElementById('flash').classList.contains('on'), null,
                               { timeout: 30000 });
    const banner = await page.evaluate(() => document.getElementById('flash').textContent);
    const frameStep = (info.times[n - 1] - info.times[0]) / Math.max(1, n - 1);
    const named = info.events.filter((o) => Math.abs(o.t - e.t) <= 2 * frameStep + 1e-12 &&
                                            banner.startsWith(`${o.kind} ${o.label} at `));
    assert.ok(named.length > 0, `the banner '${banner}' names no event near t = ${e.t} s`);
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
  console.log(`${caseName}: ${info.bodies.length} bodies, ${n} samples; ${checked} bodies' pixels checked ` +
              `(${plain} in plain view) at ` +
              `${picks.length} times, worst ${worst.toFixed(2)} px; ${info.events.length} events; no errors, no requests`);
} catch (e) {
  failed = true;
  console.error(e);
} finally {
  await browser.close();
}
process.exit(failed ? 1 : 0);
