// The browser client in headless Chromium against a daemon this test starts on a free port:
// the page waits for its first frame, a frame appears, a drag changes the picture, a click
// focuses, a scene camera is picked with its focus, an orbit that starts on a near object keeps
// its distance to it (inside the scene) while the pane says it is moving at a lower resolution
// and full size returns at rest, the wheel dollies toward a surface and stops short of it, undo
// and redo restore views, fly mode moves, the split panes keep the shot's framing, a longer focal
// length zooms in (the field of view follows), the depth of field limits shown agree with the
// thin-lens formulas, the view selector lists the daemon's debug views and shows one with the
// hybrid, the in-focus zone overlay tints the picture, the mode selector changes the mode the
// frames report, a snapshot downloads, the panel fits a 900x560 window and goes below the picture
// in upright ones (390x844, 768x1024), and a stopped daemon dims the picture under a banner.
// Screenshots of each state go to the artifact directory.
//   node client.test.mjs HDOF_BINARY ARTIFACT_DIR
// Generous timeouts and no timing asserts: lavapipe on a shared machine is slow.

import assert from 'node:assert/strict';
import { spawn } from 'node:child_process';
import { mkdirSync, writeFileSync } from 'node:fs';
import path from 'node:path';
import { chromium } from 'playwright-core';

const [hdof, artifacts] = process.argv.slice(2);
if (!hdof || !artifacts) {
  console.error('usage: node client.test.mjs HDOF_BINARY ARTIFACT_DIR');
  process.exit(2);
}
const TIMEOUT_MS = 60000;
// The pane is the window less the 272 px control panel: a 480x270 viewport.
const WINDOW = { width: 480 + 272, height: 270 };

function startDaemon() {
  const env = { ...process.env };
  delete env.HDOF_TOKEN;
  // A frame rate no moving frame here holds at full size: a drag renders smaller, whatever the
  // machine's speed, so the interactive scale shows.
  const config = path.join(artifacts, 'e2e-serve.json');
  writeFileSync(config, JSON.stringify({ target_fps: 240 }));
  const daemon = spawn(hdof, ['serve', '--port', '0', '--scene', 'builtin:dof', '--config', config], {
    env, stdio: ['ignore', 'pipe', 'pipe'],
  });
  let log = '';
  daemon.stderr.on('data', (chunk) => { log += chunk; });
  const url = new Promise((resolve, reject) => {
    let output = '';
    daemon.stdout.on('data', (chunk) => {
      output += chunk;
      const match = output.match(/http:\/\/\S+:\d+\//);
      if (match) resolve(match[0]);
    });
    daemon.on('exit', (code) => reject(new Error(`hdof serve exited (${code}) before listening:\n${log}`)));
    setTimeout(() => reject(new Error(`hdof serve printed no URL:\n${log}`)), TIMEOUT_MS).unref();
  });
  return { daemon, url, log: () => log };
}

async function stopDaemon(daemon) {
  if (daemon.exitCode !== null || daemon.signalCode !== null) return;
  const exited = new Promise((resolve) => daemon.once('exit', resolve));
  daemon.kill('SIGTERM');
  const timer = setTimeout(() => daemon.kill('SIGKILL'), 30000);
  await exited;
  clearTimeout(timer);
}

// The shown frame scaled to width x height: RGBA bytes.
function framePixels(page, width, height) {
  return page.evaluate(([w, h]) => {
    const source = document.querySelector('#pane-main > canvas');
    const canvas = Object.assign(document.createElement('canvas'), { width: w, height: h });
    const g = canvas.getContext('2d', { willReadFrequently: true });
    g.drawImage(source, 0, 0, w, h);
    return [...g.getImageData(0, 0, w, h).data];
  }, [width, height]);
}

// The shown frame as a 48x27 grey thumbnail, to tell pictures apart.
async function thumbnail(page) {
  const data = await framePixels(page, 48, 27);
  const grey = [];
  for (let i = 0; i < data.length; i += 4) grey.push((data[i] + data[i + 1] + data[i + 2]) / 3);
  return grey;
}

// How green the shown frame is: the mean of green less the mean of red and blue, over its pixels.
async function greenness(page) {
  const data = await framePixels(page, 96, 54);
  let sum = 0;
  for (let i = 0; i < data.length; i += 4) sum += data[i + 1] - (data[i] + data[i + 2]) / 2;
  return sum / (data.length / 4);
}

// The lens in the URL: focal length (mm), f-number, focus (m), blades, sensor width and height.
const lensInUrl = (page) => page.evaluate(() =>
  new URLSearchParams(location.hash.slice(1)).get('lens').split(',').map(Number));
// A distance as the panel shows it: "2.31 m", "12.5 m" or "∞".
const metres = (shown) => (shown === '∞' ? Infinity : Number.parseFloat(shown));

const meanDifference = (a, b) => a.reduce((sum, v, i) => sum + Math.abs(v - b[i]), 0) / a.length;
const text = (page, selector) => page.locator(selector).textContent();
const statsField = (page, name, pane = 'main') => text(page, `#pane-${pane} [data-field="${name}"]`);

// Waits until the view has come to rest: a frame at the still JPEG quality is shown.
async function stillFrame(page) {
  await page.waitForFunction(
    () => /quality (9\d|100)$/.test(document.querySelector('#pane-main [data-field="bytes"]').textContent),
    null, { timeout: TIMEOUT_MS });
}

async function screenshot(page, name) {
  await page.screenshot({ path: path.join(artifacts, name) });
  return path.join(artifacts, name);
}

// The camera the URL holds (5 significant digits).
async function urlCamera(page) {
  const hash = await page.evaluate(() => location.hash);
  const c = new URLSearchParams(hash.slice(1)).get('camera').split(',').map(Number);
  return { position: c.slice(0, 3), target: c.slice(3, 6), up: [0, 1, 0] };
}
const between = (a, b) => Math.hypot(...a.map((v, i) => v - b[i]));

// Waits until the URL's camera has moved away from `from`; returns it.
async function cameraMoved(page, from) {
  for (const deadline = Date.now() + TIMEOUT_MS; Date.now() < deadline;) {
    const camera = await urlCamera(page);
    if (between(camera.position, from.position) > 1e-3) return camera;
    await page.waitForTimeout(100);
  }
  throw new Error('the camera in the URL did not move');
}

// Asks the daemon, in a session of the test's own with this camera and the page's lens (which
// makes the field of view), what is under each pixel: {bounds, answers: [picked]}.
async function pickPixels(page, camera, viewport, pixels) {
  const [focal, fNumber, focus, , sensorWidth, sensorHeight] = await lensInUrl(page);
  const lens = {
    type: 'lens', seq: 1, focal_length_mm: focal, f_number: fNumber, focus_distance: focus,
    sensor_width_mm: sensorWidth, sensor_height_mm: sensorHeight,
  };
  return page.evaluate(({ camera, lens, viewport, pixels }) => new Promise((resolve, reject) => {
    const socket = new WebSocket(`ws://${location.host}/session`, 'hdof.v1');
    const answers = [];
    let bounds;
    // One at a time: the daemon keeps few unread answers for a session.
    const ask = (id) => socket.send(JSON.stringify({ type: 'pick', id, x: pixels[id][0], y: pixels[id][1] }));
    socket.onopen = () => socket.send(JSON.stringify({ type: 'hello', protocol: 1, viewport }));
    socket.onmessage = (event) => {
      if (typeof event.data !== 'string') return; // frames
      const message = JSON.parse(event.data);
      if (message.type === 'welcome') {
        bounds = message.scene.bounds;
        socket.send(JSON.stringify({ type: 'camera', seq: 1, ...camera }));
        socket.send(JSON.stringify(lens));
        ask(0);
      } else if (message.type === 'picked') {
        answers[message.id] = message;
        if (message.id + 1 < pixels.length) return ask(message.id + 1);
        socket.close();
        resolve({ bounds, answers });
      } else {
        reject(new Error(`unexpected: ${event.data}`));
      }
    };
    socket.onerror = () => reject(new Error('the pick socket failed'));
  }), { camera, lens, viewport, pixels });
}

async function run(page, url) {
  // The status's states in order, from the page's start.
  await page.addInitScript(() => {
    window.statusStates = [];
    document.addEventListener('DOMContentLoaded', () => {
      const status = document.querySelector('#status');
      new MutationObserver(() => {
        if (window.statusStates.at(-1) !== status.dataset.state) window.statusStates.push(status.dataset.state);
      }).observe(status, { attributes: true, childList: true });
    });
  });
  await page.goto(`${url}#mode=postprocess`);
  await page.waitForSelector('#status[data-state="live"]', { timeout: TIMEOUT_MS });
  const states = await page.evaluate(() => window.statusStates);
  assert.ok(states.indexOf('waiting') >= 0 && states.indexOf('waiting') < states.indexOf('live'),
    `"waiting for the first frame" comes before live: ${states}`);
  step(`connected: ${states.join(' -> ')}`);

  await page.waitForFunction(
    () => document.querySelector('[data-field="mode"]').textContent === 'postprocess',
    null, { timeout: TIMEOUT_MS });
  const size = await statsField(page, 'size');
  assert.equal(size, '480×270 px', 'the frame has the pane\'s size');
  await stillFrame(page);
  const before = await thumbnail(page);
  assert.ok(before.some((v) => v > 8), 'the frame is not black');
  step(`a frame appeared (${size})`);

  const canvas = page.locator('#pane-main > canvas');
  const box = await canvas.boundingBox();
  const centre = { x: box.x + box.width / 2, y: box.y + box.height / 2 };
  await page.mouse.move(centre.x, centre.y);
  await page.mouse.down();
  await page.mouse.move(centre.x + 90, centre.y + 20, { steps: 10 });
  await page.mouse.up();
  await page.waitForFunction(() => location.hash.includes('camera='), null, { timeout: TIMEOUT_MS });
  await stillFrame(page);
  let difference = 0;
  for (const deadline = Date.now() + TIMEOUT_MS; difference < 4 && Date.now() < deadline;) {
    await page.waitForTimeout(250);
    difference = meanDifference(before, await thumbnail(page));
  }
  assert.ok(difference >= 4, `a drag changes the picture (mean difference ${difference.toFixed(2)})`);
  step(`a drag changed the picture (mean difference ${difference.toFixed(1)} of 255)`);

  // Click points until one lands on a surface at another depth than the focus (the background
  // keeps the focus where it is).
  const focusBefore = await text(page, '#focus-distance');
  let focusAfter = focusBefore;
  for (const [u, v] of [[0.5, 0.7], [0.3, 0.6], [0.7, 0.6], [0.5, 0.85], [0.2, 0.8], [0.8, 0.8]]) {
    await page.mouse.click(box.x + box.width * u, box.y + box.height * v);
    try {
      await page.waitForFunction(
        (old) => document.querySelector('#focus-distance').textContent !== old,
        focusBefore, { timeout: 15000 });
    } catch {
      continue;
    }
    await page.waitForTimeout(1500); // the pull's end
    focusAfter = await text(page, '#focus-distance');
    break;
  }
  assert.notEqual(focusAfter, focusBefore, 'a click focuses on the surface under the cursor');
  step(`click to focus: ${focusBefore} -> ${focusAfter}`);

  // Picking a scene camera shows it in the picker and applies its focus (builtin:dof's camera
  // suggests 4 m).
  await page.selectOption('#cameras', '0');
  await page.waitForFunction(
    () => document.querySelector('#focus-distance').textContent === '4.00 m', null,
    { timeout: TIMEOUT_MS });
  await stillFrame(page);
  assert.equal(await page.$eval('#cameras', (select) => select.value), '0',
    'the picked camera stays shown');
  step('a scene camera picked: shown in the picker, its focus 4.00 m applied');

  await navigation(page, box);
  // Back to the scene camera's view (its subject at the 4 m focus) for the lens's steps.
  await page.selectOption('#cameras', '0');
  await page.waitForFunction(() => document.querySelector('#cameras').value === '0');
  await page.waitForTimeout(600); // the view changes in the URL within 250 ms
  await stillFrame(page);

  // A longer lens zooms in: the picture changes and the field of view the frames report follows
  // 2 atan(extent / 2f), where a 16:9 pane takes 36 x 20.25 mm of the full-frame sensor.
  const wide = await thumbnail(page);
  const fovBefore = await text(page, '#fov');
  const [focalBefore] = await lensInUrl(page);
  await page.locator('input[name="focal_length_mm"]').fill('600'); // 8 mm * 50^0.6 = 84 mm
  await page.waitForFunction((f) => !location.hash.includes(`lens=${f},`), focalBefore);
  const [focal, fNumber, focus, , sensorWidth, sensorHeight] = await lensInUrl(page);
  assert.ok(focal > focalBefore, `the focal length grew: ${focalBefore} -> ${focal} mm`);
  assert.deepEqual([sensorWidth, sensorHeight], [36, 24], 'full frame by default');
  await page.waitForFunction((old) => document.querySelector('#fov').textContent !== old, fovBefore,
    { timeout: TIMEOUT_MS });
  await stillFrame(page);
  const fovShown = (await text(page, '#fov')).split('×').map((v) => Number.parseFloat(v));
  const fovDeg = (extent) => (360 / Math.PI) * Math.atan(extent / (2 * focal));
  assert.ok(Math.abs(fovShown[0] - fovDeg(36)) < 0.06 && Math.abs(fovShown[1] - fovDeg(20.25)) < 0.06,
    `field of view ${fovShown} follows ${focal} mm: ${fovDeg(36).toFixed(2)} x ${fovDeg(20.25).toFixed(2)}`);
  difference = meanDifference(wide, await thumbnail(page));
  assert.ok(difference >= 4, `a longer lens changes the framing (mean difference ${difference.toFixed(2)})`);
  await page.screenshot({ path: path.join(artifacts, 'client-lens-long.png') });
  step(`focal length ${focalBefore} -> ${focal} mm: field of view ${fovBefore} -> ` +
    `${fovShown.join(' x ')} (screenshot ${path.join(artifacts, 'client-lens-long.png')})`);

  // The depth of field shown is the thin-lens formulas' with c = diagonal / 1500.
  const c = Math.hypot(sensorWidth, sensorHeight) / 1500 / 1000;
  const f = focal / 1000;
  const hyperfocal = (f * f) / (fNumber * c) + f;
  const expected = {
    near: (focus * (hyperfocal - f)) / (hyperfocal + focus - 2 * f),
    far: focus < hyperfocal ? (focus * (hyperfocal - f)) / (hyperfocal - focus) : Infinity,
    hyperfocal,
  };
  for (const [name, value] of Object.entries(expected)) {
    const shown = metres(await text(page, `#dof-${name}`));
    const tolerance = value === Infinity ? 0 : value < 10 ? 0.006 : 0.06; // the shown rounding
    assert.ok(shown === value || Math.abs(shown - value) <= tolerance,
      `${name}: shown ${shown} m, the formula gives ${value} m (${focal} mm f/${fNumber} at ${focus} m)`);
  }
  assert.match(await text(page, '#dof-coc'), /^0\.0288 mm \(sensor diagonal \/ 1500\)$/);
  const scale = await page.evaluate(() => ['.dof-zone', '.dof-focus'].map((s) =>
    document.querySelector(s).getBoundingClientRect()));
  const marker = (scale[1].left + scale[1].right) / 2; // the triangle's tip
  assert.ok(marker >= scale[0].left - 0.5 && marker <= scale[0].right + 0.5,
    `the focus marker (${marker}) sits inside the in-focus zone (${scale[0].left}-${scale[0].right})`);
  await page.locator('.dof-scale').scrollIntoViewIfNeeded();
  await page.screenshot({ path: path.join(artifacts, 'client-dof.png') });
  step(`depth of field near ${expected.near.toFixed(2)} m, far ${expected.far.toFixed(2)} m, ` +
    `hyperfocal ${hyperfocal.toFixed(1)} m as shown (screenshot ${path.join(artifacts, 'client-dof.png')})`);

  // The view selector is the welcome's views (asked here of a session of its own), and it is
  // only for the hybrid.
  const views = await page.evaluate(() => new Promise((resolve, reject) => {
    const socket = new WebSocket(`ws://${location.host}/session`, 'hdof.v1');
    socket.onopen = () => socket.send(JSON.stringify(
      { type: 'hello', protocol: 1, viewport: { width: 16, height: 16 } }));
    socket.onmessage = (event) => {
      const message = JSON.parse(event.data);
      socket.close();
      if (message.type === 'welcome') resolve(message.views);
      else reject(new Error(`no welcome: ${event.data}`));
    };
    socket.onerror = () => reject(new Error('the welcome socket failed'));
  }));
  assert.ok(Array.isArray(views) && views.length > 1, `the welcome lists views: ${views}`);
  const options = () => page.$$eval('#view option', (list) => list.map((o) => o.value));
  assert.deepEqual(await options(), views, 'the view selector lists the welcome\'s views');
  assert.equal(await page.inputValue('#view'), views[0], 'the finished image is shown first');
  assert.ok(await page.isDisabled('#view'), 'no debug views outside the hybrid');
  await page.selectOption('#mode', 'hybrid');
  await page.waitForFunction(
    () => document.querySelector('[data-field="mode"]').textContent === 'hybrid',
    null, { timeout: TIMEOUT_MS });
  assert.ok(await page.isEnabled('#view'), 'the hybrid has debug views');
  const plain = await thumbnail(page);
  await page.selectOption('#view', views[1]);
  await page.waitForFunction((view) => location.hash.includes(`view=${view}`), views[1]);
  difference = 0;
  for (const deadline = Date.now() + TIMEOUT_MS; difference < 4 && Date.now() < deadline;) {
    await page.waitForTimeout(250);
    difference = meanDifference(plain, await thumbnail(page));
  }
  assert.ok(difference >= 4, `the ${views[1]} view changes the picture (mean difference ${difference.toFixed(2)})`);
  await page.locator('#view').scrollIntoViewIfNeeded(); // the 270 px window hides the panel's end
  await page.screenshot({ path: path.join(artifacts, 'client-view.png') });
  step(`the view selector lists ${views.join(', ')}; ${views[1]} shown ` +
    `(screenshot ${path.join(artifacts, 'client-view.png')})`);

  // The in-focus zone overlay: the daemon's focus_zone view tints the finished image green.
  await page.selectOption('#view', views[0]);
  await page.waitForFunction(() => !location.hash.includes('view='));
  await stillFrame(page);
  const plainGreen = await greenness(page);
  await page.locator('#focus-zone').scrollIntoViewIfNeeded();
  await page.check('#focus-zone');
  await page.waitForFunction(() => location.hash.includes('view=focus_zone'));
  assert.equal(await page.inputValue('#view'), 'focus_zone', 'the view selector follows');
  let green = plainGreen;
  for (const deadline = Date.now() + TIMEOUT_MS; green < plainGreen + 5 && Date.now() < deadline;) {
    await page.waitForTimeout(250);
    green = await greenness(page);
  }
  assert.ok(green >= plainGreen + 5, `the in-focus zone is tinted green (${plainGreen.toFixed(1)} -> ${green.toFixed(1)})`);
  await page.screenshot({ path: path.join(artifacts, 'client-focus-zone.png') });
  step(`in-focus zone overlay: greenness ${plainGreen.toFixed(1)} -> ${green.toFixed(1)} ` +
    `(screenshot ${path.join(artifacts, 'client-focus-zone.png')})`);
  await page.uncheck('#focus-zone');

  await page.selectOption('#mode', 'pinhole');
  await page.waitForFunction(
    () => document.querySelector('[data-field="mode"]').textContent === 'pinhole',
    null, { timeout: TIMEOUT_MS });
  await page.waitForFunction(() => location.hash.includes('mode=pinhole')); // the URL follows
  assert.ok(await page.isDisabled('#view'), 'no debug views outside the hybrid');
  step('the mode selector changed the mode in the stats');

  const [download] = await Promise.all([
    page.waitForEvent('download', { timeout: TIMEOUT_MS }),
    page.click('#snapshot'),
  ]);
  const name = download.suggestedFilename();
  assert.match(name, /^hdof-pinhole-f[\d.]+-\d+mm-focus[\d.]+m\.png$/, 'the snapshot is named by its lens');
  await download.saveAs(path.join(artifacts, name));
  step(`snapshot ${name}`);

  await page.screenshot({ path: path.join(artifacts, 'client.png') });
  step(`screenshot ${path.join(artifacts, 'client.png')}`);

  // The control panel fits a 900x560 window without scrolling (once the snapshot's note is gone).
  await page.setViewportSize({ width: 900, height: 560 });
  await page.waitForSelector('#share-note', { state: 'hidden', timeout: TIMEOUT_MS });
  await page.waitForFunction(() => document.querySelector('#pane-main [data-field="size"]').textContent.endsWith('560 px'),
    null, { timeout: TIMEOUT_MS });
  const [scrolled, shown] = await page.$eval('#controls', (panel) => [panel.scrollHeight, panel.clientHeight]);
  assert.ok(scrolled <= shown, `the panel fits at 900x560: ${scrolled} px of content in ${shown} px`);
  step(`the panel fits at 900x560 (${await screenshot(page, 'client-900x560.png')})`);

  // A phone and a tablet held upright: the picture takes the window's width above the panel, and
  // nothing scrolls sideways.
  for (const [width, height] of [[390, 844], [768, 1024]]) {
    await page.setViewportSize({ width, height });
    await page.waitForFunction((w) => document.querySelector('#pane-main [data-field="size"]').textContent.startsWith(`${w}×`),
      width, { timeout: TIMEOUT_MS });
    const layout = await page.evaluate(() => {
      const pane = document.querySelector('#pane-main').getBoundingClientRect();
      const panel = document.querySelector('#controls').getBoundingClientRect();
      return { paneWidth: pane.width, paneBottom: pane.bottom, panelTop: panel.top,
        scrollWidth: document.documentElement.scrollWidth };
    });
    assert.equal(layout.paneWidth, width, `the picture spans an upright ${width}x${height} window`);
    assert.ok(layout.panelTop >= layout.paneBottom - 1, `the panel is below the picture: ${JSON.stringify(layout)}`);
    assert.ok(layout.scrollWidth <= width, `nothing scrolls sideways: ${layout.scrollWidth} px`);
    // The resize started a new session: its first frame shown is already in the chosen mode, not
    // in the daemon's default one.
    const [shownMode, chosenMode] = await page.evaluate(() => [
      document.querySelector('#pane-main .pane-label [data-field="mode"]').textContent,
      document.querySelector('#mode').value]);
    assert.equal(shownMode, chosenMode, 'the first frame after a resize is in the chosen mode');
    const shot = await screenshot(page, `client-${width}x${height}.png`);
    step(`a ${width}x${height} window puts the panel below the picture (${shot})`);
  }
  await page.setViewportSize(WINDOW);
}

// Orbit about a near object, the interactive scale, dolly, undo and redo, fly mode, split view.
async function navigation(page, box) {
  const viewport = { width: 480, height: 270 };
  await page.waitForTimeout(600); // the URL follows the view within 250 ms
  const start = await urlCamera(page);
  // The nearest surface on a grid of pixels: the near object the orbit starts on.
  const grid = [];
  for (let y = 20; y < viewport.height; y += 25) for (let x = 20; x < viewport.width; x += 40) grid.push([x, y]);
  const { bounds, answers } = await pickPixels(page, start, viewport, grid);
  const hits = answers.map((a, i) => ({ ...a, pixel: grid[i] })).filter((a) => a.hit);
  const nearest = hits.reduce((a, b) => (b.distance < a.distance ? b : a));
  const farthest = hits.reduce((a, b) => (b.distance > a.distance ? b : a));
  assert.ok(nearest.distance < 0.5 * farthest.distance, 'the scene has a near object');
  const at = { x: box.x + nearest.pixel[0] + 0.5, y: box.y + nearest.pixel[1] + 0.5 };

  // Drag from the near object until a moving frame at a lower resolution is shown.
  await page.mouse.move(at.x, at.y);
  await page.mouse.down();
  let moving = '';
  let dx = 0;
  for (const deadline = Date.now() + TIMEOUT_MS; !/^moving: \d+%$/.test(moving) && Date.now() < deadline;) {
    dx = dx >= 120 ? 10 : dx + 10; // back and forth: the drag goes on as long as it must
    await page.mouse.move(at.x + dx, at.y - dx / 4, { steps: 2 });
    await page.waitForTimeout(100);
    moving = await statsField(page, 'state');
  }
  assert.match(moving, /^moving: \d+%$/, 'a drag shows the interactive scale');
  assert.ok(await page.isVisible('#pane-main .pivot'), 'the pivot marker shows while orbiting');
  const movingShot = await screenshot(page, 'client-orbit-moving.png');
  await page.mouse.up();
  await page.waitForFunction(() => !document.querySelector('#pane-main .pivot').checkVisibility());
  await cameraMoved(page, start);
  await page.waitForTimeout(400); // the URL follows the view within 250 ms
  const orbited = await urlCamera(page);
  const before = between(start.position, nearest.point);
  const after = between(orbited.position, nearest.point);
  assert.ok(Math.abs(after - before) < 0.01 * before,
    `the orbit keeps the camera's distance to the pivot (${before.toFixed(3)} m, then ${after.toFixed(3)} m)`);
  assert.ok(between(orbited.position, start.position) > 0.05 * before, 'the camera moved');
  assert.ok(orbited.position.every((v, i) => v >= bounds.min[i] && v <= bounds.max[i]),
    `the camera stays inside the scene: ${orbited.position}`);
  step(`orbit about the near object at ${before.toFixed(2)} m: distance kept (${after.toFixed(2)} m), ` +
    `"${moving}" while dragging (${movingShot})`);

  await page.waitForFunction(
    () => /^(refining|converged)/.test(document.querySelector('#pane-main [data-field="state"]').textContent),
    null, { timeout: TIMEOUT_MS });
  assert.equal(await statsField(page, 'size'), '480×270 px', 'full size at rest');
  step(`at rest: ${await statsField(page, 'state')} at full size (${await screenshot(page, 'client-orbit-rest.png')})`);

  // The wheel toward the pivot (where the drag started: an orbit keeps it in place).
  await page.mouse.move(at.x, at.y);
  for (let i = 0; i < 40; i++) await page.mouse.wheel(0, -100);
  await stillFrame(page);
  const dollied = await urlCamera(page);
  const standoff = Math.max(0.05, between(bounds.max, bounds.min) * 0.005);
  const left = between(dollied.position, nearest.point);
  assert.ok(left < 0.3 * before, `the dolly moved toward the surface (${left.toFixed(3)} m left)`);
  const [again] = (await pickPixels(page, dollied, viewport, [nearest.pixel])).answers;
  assert.ok(again.hit && again.distance >= 0.5 * standoff,
    `the dolly stopped short of the surface: ${JSON.stringify(again)}, standoff ${standoff} m`);
  step(`40 wheel notches stop ${again.distance.toFixed(3)} m short of the surface ` +
    `(${await screenshot(page, 'client-dolly.png')})`);

  // Undo back to the scene camera's view, then redo.
  for (let i = 0; i < 5 && between((await urlCamera(page)).position, start.position) > 1e-3; i++) {
    await page.keyboard.press('Control+z');
    await page.waitForTimeout(400); // the URL follows every 250 ms
  }
  assert.ok(between((await urlCamera(page)).position, start.position) < 1e-3, 'undo restores the view');
  await page.click('#redo');
  await cameraMoved(page, start); // redo moves again
  await stillFrame(page);
  step(`undo restores the scene camera's view, redo moves again (${await screenshot(page, 'client-undo.png')})`);

  // Fly: W moves along the view direction.
  const flyFrom = await urlCamera(page);
  await page.click('#fly');
  assert.equal(await page.getAttribute('#fly', 'aria-pressed'), 'true');
  await page.keyboard.down('KeyW');
  await page.waitForTimeout(600);
  await page.keyboard.up('KeyW');
  const flown = await cameraMoved(page, flyFrom);
  const forward = flyFrom.target.map((v, i) => v - flyFrom.position[i]);
  const moved = flown.position.map((v, i) => v - flyFrom.position[i]);
  assert.ok(moved.reduce((sum, v, i) => sum + v * forward[i], 0) > 0, 'W flies forward');
  await page.keyboard.press('f');
  assert.equal(await page.getAttribute('#fly', 'aria-pressed'), 'false', 'F leaves fly mode');
  await stillFrame(page);
  step(`fly mode: W moved ${between(flown.position, flyFrom.position).toFixed(2)} m forward ` +
    `(${await screenshot(page, 'client-fly.png')})`);

  // The split view: each pane shows the whole shot (its aspect), labelled with its mode.
  await page.check('#split');
  await page.waitForFunction(() => document.querySelector('#pane-compare [data-field="mode"]').textContent === 'postprocess',
    null, { timeout: TIMEOUT_MS });
  await page.waitForFunction(() => !document.querySelector('#pane-main [data-field="size"]').textContent.startsWith('480'),
    null, { timeout: TIMEOUT_MS });
  for (const pane of ['main', 'compare']) {
    const [w, h] = (await statsField(page, 'size', pane)).match(/\d+/g).map(Number);
    assert.ok(Math.abs(w / h - 480 / 270) < 0.02, `the ${pane} pane keeps the shot's framing: ${w}x${h}`);
  }
  const labels = `${await statsField(page, 'mode', 'main')} | ${await statsField(page, 'mode', 'compare')}`;
  step(`split: both panes ${await statsField(page, 'size', 'compare')}, the shot's aspect, labelled ${labels} ` +
    `(${await screenshot(page, 'client-split.png')})`);
  await page.uncheck('#split');
  await page.waitForFunction(() => document.querySelector('#pane-main [data-field="size"]').textContent === '480×270 px',
    null, { timeout: TIMEOUT_MS });
}

// The daemon stops: the picture dims under a banner, and a click says it was not sent.
async function disconnected(page, daemon) {
  await stopDaemon(daemon);
  await page.waitForSelector('#pane-main .banner:not([hidden])', { timeout: TIMEOUT_MS });
  const banner = await text(page, '#pane-main .banner');
  assert.match(banner, /^Disconnected: the daemon stopped/, banner);
  assert.ok(await page.$eval('#pane-main', (pane) => pane.classList.contains('disconnected')), 'the picture is dimmed');
  const box = await page.locator('#pane-main > canvas').boundingBox();
  await page.mouse.click(box.x + box.width / 2, box.y + box.height / 2);
  assert.match(await text(page, '[data-error-for="general"]'), /Not connected/);
  step(`daemon stopped: "${banner}" (${await screenshot(page, 'client-disconnected.png')})`);
}

const started = Date.now();
function step(message) {
  console.log(`ok (${((Date.now() - started) / 1000).toFixed(1)} s): ${message}`);
}

async function main() {
  mkdirSync(artifacts, { recursive: true });
  const { daemon, url, log } = startDaemon();
  let browser;
  try {
    const address = await url;
    step(`hdof serve at ${address}`);
    browser = await chromium.launch({
      executablePath: '/usr/bin/chromium',
      headless: true,
      args: ['--no-sandbox', '--disable-gpu', '--disable-background-networking',
        '--disable-component-update', '--disable-sync'],
      timeout: TIMEOUT_MS,
    });
    const page = await browser.newPage({ viewport: WINDOW, acceptDownloads: true });
    const pageErrors = [];
    page.on('pageerror', (error) => pageErrors.push(error.message));
    page.on('console', (message) => {
      // Chromium logs each refused reconnection once the daemon is stopped on purpose.
      if (message.type() === 'error' && !/WebSocket connection to .* failed/.test(message.text()))
        pageErrors.push(message.text());
    });
    page.setDefaultTimeout(TIMEOUT_MS);
    try {
      await run(page, address);
      await disconnected(page, daemon);
    } catch (error) {
      await page.screenshot({ path: path.join(artifacts, 'failure.png') }).catch(() => {});
      throw error;
    }
    assert.deepEqual(pageErrors, [], 'no errors in the page');
  } catch (error) {
    console.error(`FAILED: ${error.stack ?? error}\n--- hdof serve log ---\n${log()}`);
    process.exitCode = 1;
  } finally {
    await browser?.close().catch(() => {});
    step('browser closed');
    await stopDaemon(daemon);
    step('hdof serve stopped');
  }
}

await main();
