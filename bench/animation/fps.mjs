// Frame rate of the animation page in headless Chromium on this machine's
// software renderer (SwiftShader): opens PAGE, plays it for SECONDS with the
// page's own frame counter, prints frames/s and what the page's status line
// says. Usage: node fps.mjs PAGE [SECONDS] [WIDTHxHEIGHT] [SPEED]
// (SPEED: simulated seconds per second of playback; default the page's own).
// (docs/performance.md has the figures and the command that made the page).
const { chromium } = await import(new URL('../../web/node_modules/playwright-core/index.mjs', import.meta.url));
const [file, secondsText = '6', size = '1200x700', speedText] = process.argv.slice(2);
const [width, height] = size.split('x').map(Number);
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || '/usr/bin/chromium',
  args: ['--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
         '--disable-background-networking', '--disable-component-update', '--disable-sync', '--no-first-run'],
});
const page = await browser.newPage({ viewport: { width, height } });
const t0 = Date.now();
await page.goto('file://' + file);
await page.waitForFunction(() => window.lagrangian && window.lagrangian.ready, null, { timeout: 120000 });
const loaded = (Date.now() - t0) / 1000;
await page.evaluate((wanted) => {
  const speed = document.getElementById('speed');
  if (wanted) speed.value = wanted;
  window.lagrangian.play(true);
}, speedText);
const samples = [];
const until = Date.now() + 1000 * Number(secondsText);
while (Date.now() < until) {
  await new Promise((r) => setTimeout(r, 1000));
  // playback stops at the end: start again
  await page.evaluate(() => { if (document.getElementById('play').textContent.includes('play')) window.lagrangian.play(true); });
  const s = await page.evaluate(() => ({ fps: window.lagrangian.state().fps,
                                         status: document.getElementById('status').textContent }));
  samples.push(s);
}
const fps = samples.slice(1).map((s) => s.fps).filter((v) => v > 0);
fps.sort((a, b) => a - b);
console.log(`page loaded in ${loaded.toFixed(1)} s; frames/s over ${fps.length} s: median ${fps[fps.length >> 1].toFixed(1)}, ` +
            `min ${fps[0].toFixed(1)}, max ${fps[fps.length - 1].toFixed(1)}`);
console.log('status: ' + samples[samples.length - 1].status);
await browser.close();
