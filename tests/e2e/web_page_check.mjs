// Drives Debian's chromium (headless, WebGL through SwiftShader) with playwright-core from
// viewer/web/node_modules: opens an mbstream-viewer --web page, waits for frames (events,
// never fixed sleeps), records what the page draws, opens a second page, takes a screenshot.
// Usage: node web_page_check.mjs URL OUT_DIR WEB_ROOT
//   [replay | denied | watch-only:TOKEN | stall:FRAMES]
// (`denied`: pages with a token lacking the view role and with none are refused; an https URL
// is opened with --ignore-certificate-errors, the test's certificate being self-signed;
// `watch-only:TOKEN`: URL's page (a view token) cannot steer the replay, a page with TOKEN
// (the run role) pauses it for both; `replay` also sets the speed from the page and measures
// the replay's pace; `stall:FRAMES`: a page in a second browser is stalled, its processes
// stopped (SIGSTOP: a laptop's lid closed), while the first page gets FRAMES frames, then
// woken: its missed count rises, the first page keeps pace)
// Prints one JSON object on stdout: the figures and the recorded frames.
import { createRequire } from 'node:module';
import process from 'node:process';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';

const [url, outDir, webRoot, modeArg] = process.argv.slice(2);
const [mode, steerToken] = (modeArg || '').split(':');
const require = createRequire(resolve(webRoot, 'package.json'));
const { chromium } = require('playwright-core');

const launchArgs = ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
  '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--use-gl=swiftshader', '--enable-unsafe-swiftshader', '--ignore-gpu-blocklist'];
const profile = mkdtempSync(join(tmpdir(), 'mbstream-chromium-'));
const context = await chromium.launchPersistentContext(profile, {
  executablePath: '/usr/bin/chromium',
  headless: true,
  viewport: { width: 800, height: 600 },
  args: [...launchArgs, ...(url.startsWith('https:') ? ['--ignore-certificate-errors'] : [])],
});
const result = {};
const outside = [];  // requests to anywhere but the viewer
try {
  const page = context.pages()[0] || await context.newPage();
  const origin = new URL(url).origin;
  page.on('request', (request) => {
    if (!request.url().startsWith(origin) && !request.url().startsWith('data:')) outside.push(request.url());
  });
  const errors = [];
  page.on('pageerror', (error) => errors.push(String(error)));
  const start = Date.now();
  await page.goto(url, { waitUntil: 'load' });
  result.load_ms = Date.now() - start;
  await page.waitForFunction(() => window.mbstream && window.mbstream.frames >= 1 &&
                             window.mbstream.rendered >= 1, null, { timeout: 60000 });
  result.first_frame_ms = Date.now() - start;
  result.page_bytes = await page.evaluate(() => performance.getEntriesByType('resource')
    .concat(performance.getEntriesByType('navigation'))
    .reduce((n, e) => n + (e.transferSize || e.encodedBodySize || 0), 0));
  await page.evaluate(() => { window.mbstream.record = []; });
  const frames = Number(mode === 'replay' ? 10 : 40);
  await page.waitForFunction((n) => window.mbstream.record.length >= n, frames, { timeout: 60000 });

  if (mode === 'replay') {
    // Pause, step on twice, seek: the page's controls reach the viewer's replay.
    await page.evaluate(() => window.mbstream.send({ pause: true }));
    await page.waitForFunction(() => window.mbstream.paused === true, null, { timeout: 30000 });
    const paused = await page.evaluate(() => window.mbstream.seq);
    await page.keyboard.press('ArrowRight');
    await page.waitForFunction((s) => window.mbstream.seq === s + 1, paused, { timeout: 30000 });
    await page.evaluate(() => window.mbstream.send({ seek_seq: 100 }));
    await page.waitForFunction(() => window.mbstream.seq === 100, null, { timeout: 30000 });
    result.replay = { paused_at: paused, after_step: paused + 1,
                      after_seek: await page.evaluate(() => window.mbstream.seq),
                      compare: await page.evaluate(() => window.mbstream.compare),
                      ghost_distance: await page.evaluate(() => window.mbstream.ghost_distance) };
    await page.evaluate(() => window.mbstream.send({ resume: true }));
    // Speed from the page's control: the replay's run time per wall second follows it (x5,
    // then x1), and the viewer reports the speed in its frames.
    const pace = async (span) => {  // span: run seconds to time
      for (;;) {
        const a = await page.evaluate(() => ({ t: window.mbstream.t, at: performance.now() }));
        await page.waitForFunction(([t0, dt]) => window.mbstream.t >= t0 + dt || window.mbstream.t < t0,
                                   [a.t, span], { timeout: 30000 });
        const b = await page.evaluate(() => ({ t: window.mbstream.t, at: performance.now() }));
        if (b.t > a.t) return (b.t - a.t) / ((b.at - a.at) / 1000);  // else it looped: again
      }
    };
    await page.waitForFunction(() => window.mbstream.paused === false, null, { timeout: 30000 });
    await page.selectOption('#speed', '5');
    await page.waitForFunction(() => window.mbstream.speed === 5, null, { timeout: 30000 });
    const fast = await pace(4.0);
    await page.selectOption('#speed', '1');
    await page.waitForFunction(() => window.mbstream.speed === 1, null, { timeout: 30000 });
    const slow = await pace(1.0);
    // The speeds the viewer's frames reported (the waits above saw them): the assertions.
    // The paces are figures only, printed by the test: wall time is the machine's.
    result.replay.speed = { fast, slow, reported: [5, await page.evaluate(() => window.mbstream.speed)] };
  }

  if (mode === 'stall') {
    // A page in a second browser, stopped whole (its browser, network and renderer
    // processes) while the first page gets FRAMES frames, then woken.
    const frames = Number(steerToken || 200);
    const server = await chromium.launchServer({ executablePath: '/usr/bin/chromium',
                                                 headless: true, args: launchArgs });
    const other = await chromium.connect(server.wsEndpoint());
    try {
      const stalled = await other.newPage();
      await stalled.goto(url, { waitUntil: 'load' });
      await stalled.waitForFunction(() => window.mbstream && window.mbstream.frames >= 5, null,
                                    { timeout: 60000 });
      const read = (p) => p.evaluate(() => ({ seq: window.mbstream.seq, frames: window.mbstream.frames,
        missed: window.mbstream.missed, viewer_frames: window.mbstream.viewer_frames }));
      const stalledBefore = await read(stalled);
      const before = await read(page);
      const group = server.process().pid;  // playwright starts it as a process group's leader
      process.kill(-group, 'SIGSTOP');
      try {
        await page.waitForFunction((n) => window.mbstream.frames >= n, before.frames + frames,
                                   { timeout: 120000 });
      } finally {
        process.kill(-group, 'SIGCONT');
      }
      const after = await read(page);
      await stalled.waitForFunction((m) => window.mbstream.missed > m, stalledBefore.missed,
                                    { timeout: 60000 });
      result.stall = { before, after, stalled_before: stalledBefore,
                       stalled_after: await read(stalled),
                       stalled_hud: await stalled.evaluate(() => document.getElementById('hud').textContent) };
    } finally {
      await other.close();
      await server.close();
    }
  }

  if (mode === 'watch-only') {
    // Its control is refused (the viewer says so) and the replay plays on.
    result.watch_only = { controls: await page.evaluate(() => window.mbstream.controls),
                          disabled: await page.evaluate(() => document.getElementById('play').disabled) };
    await page.evaluate(() => window.mbstream.send({ pause: true }));
    await page.waitForFunction(() => window.mbstream.control_refused >= 1, null, { timeout: 30000 });
    const at = await page.evaluate(() => window.mbstream.seq);
    await page.waitForFunction((s) => window.mbstream.seq !== s, at, { timeout: 30000 });
    result.watch_only.paused_after = await page.evaluate(() => window.mbstream.paused);
    result.watch_only.message = await page.evaluate(() => window.mbstream.controls_message);
    // A page with the run role pauses the replay: for every page.
    const steering = await context.newPage();
    await steering.goto(new URL(url).origin + '/#token=' + steerToken, { waitUntil: 'load' });
    await steering.waitForFunction(() => window.mbstream && window.mbstream.frames >= 1, null,
                                   { timeout: 60000 });
    result.watch_only.steer_controls = await steering.evaluate(() => window.mbstream.controls);
    await steering.evaluate(() => window.mbstream.send({ pause: true }));
    await steering.waitForFunction(() => window.mbstream.paused === true, null, { timeout: 30000 });
    await page.waitForFunction(() => window.mbstream.paused === true, null, { timeout: 30000 });
    result.watch_only.paused_for_both = true;
    await steering.evaluate(() => window.mbstream.send({ resume: true }));
    await steering.close();
  }

  // A second page opened now shows the same run at once (the snapshot on connect).
  const second = await context.newPage();
  const joined = Date.now();
  await second.goto(url, { waitUntil: 'load' });
  await second.waitForFunction(() => window.mbstream && window.mbstream.frames >= 1 &&
                               window.mbstream.rendered >= 1, null, { timeout: 60000 });
  result.late_join_ms = Date.now() - joined;
  result.second_run = await second.evaluate(() => window.mbstream.run);
  await second.close();

  if (mode === 'denied') {
    // The token left the address bar; pages without the view role, or without a token, get
    // nothing but the refusal (and its form).
    result.hash_after_load = await page.evaluate(() => location.hash);
    result.protocol = await page.evaluate(() => location.protocol);
    result.refused = [];
    for (const fragment of ['#token=not-a-viewer-token', '']) {
      const refused = await context.newPage();
      await refused.goto(origin + '/' + fragment, { waitUntil: 'load' });
      await refused.waitForFunction(() => window.mbstream && window.mbstream.denied, null,
                                    { timeout: 30000 });
      result.refused.push(await refused.evaluate(() => ({
        status: window.mbstream.denied.status, message: window.mbstream.denied.message,
        scene: window.mbstream.scene, frames: window.mbstream.frames,
        form: !document.getElementById('login').hidden })));
      await refused.close();
    }
  }

  await page.screenshot({ path: join(outDir, 'web_page.png') });
  // The robot's pixels: the canvas is transparent where nothing is drawn.
  result.drawn_fraction = await page.evaluate(() => {
    const gl = document.querySelector('#view canvas');
    const canvas = document.createElement('canvas');
    canvas.width = gl.width; canvas.height = gl.height;
    const context2d = canvas.getContext('2d');
    context2d.drawImage(gl, 0, 0);
    const data = context2d.getImageData(0, 0, canvas.width, canvas.height).data;
    let drawn = 0;
    for (let i = 3; i < data.length; i += 4) if (data[i] > 0) ++drawn;
    let red = 0;  // strongly red pixels (a test's red texture; no default colour is)
    for (let i = 0; i < data.length; i += 4) {
      if (data[i + 3] > 0 && data[i] > 60 && data[i] > 2 * data[i + 1] && data[i] > 2 * data[i + 2]) ++red;
    }
    return { drawn: drawn / (canvas.width * canvas.height), red: red / (canvas.width * canvas.height) };
  });
  result.red_fraction = result.drawn_fraction.red;
  result.drawn_fraction = result.drawn_fraction.drawn;
  const state = await page.evaluate(() => ({
    run: window.mbstream.run, state: window.mbstream.state, frames: window.mbstream.frames,
    missed: window.mbstream.missed, scene_bytes: window.mbstream.scene_bytes,
    frame_bytes: window.mbstream.frame_bytes, triangles: window.mbstream.triangles,
    parts: window.mbstream.parts,
    latency_ms: window.mbstream.latency_ms, record: window.mbstream.record,
    hud: document.getElementById('hud').textContent }));
  Object.assign(result, state);
  result.errors = errors;
  result.outside = outside;
} finally {
  await context.close();
  rmSync(profile, { recursive: true, force: true });
}
process.stdout.write(JSON.stringify(result) + '\n');
