// What the lab's browser tests share (browser.test.mjs, classroom.test.mjs,
// the redraw bench): where the program, the records and Chromium are; the
// records-missing rule (under CI=true a missing browser or record fails the
// test, otherwise it is skipped loudly with CTest's skip code 77);
// `rocking serve` started on a free port it prints, serving the lab/ folder
// of the checkout the tests belong to; Debian's headless
// Chromium launched through puppeteer-core; and the waits for the page's runs.
//
// Environment: ROCKING_BIN (the program; default build/bin/rocking),
// ROCKING_RECORDS (the records; default ../shared/data/records), CI.
import { spawn } from 'node:child_process';
import { existsSync } from 'node:fs';
import { dirname, join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

export const repo = resolve(dirname(fileURLToPath(import.meta.url)), '..', '..');
export const bin = process.env.ROCKING_BIN || join(repo, 'build', 'bin', 'rocking');
export const records = process.env.ROCKING_RECORDS || join(repo, '..', 'shared', 'data', 'records');
export const chromium = '/usr/bin/chromium';

// Exits: 1 under CI=true, else 77 (CTest's SKIP_RETURN_CODE) with a loud line.
export function skipOrFail(test, why) {
  if (process.env.CI === 'true') {
    console.error(`${test}: ${why}`);
    process.exit(1);
  }
  console.error(`${test} SKIPPED: ${why}`);
  process.exit(77);
}

// Skips (or fails) `test` unless Chromium and each of `needed` records are there.
export function requireBrowserAndRecords(test, needed) {
  if (!existsSync(chromium)) skipOrFail(test, `${chromium} is missing (scripts/setup.sh installs Debian's chromium)`);
  for (const r of needed)
    if (!existsSync(join(records, r))) skipOrFail(test, `${join(records, r)} is missing (set ROCKING_RECORDS)`);
}

// `rocking serve` on a free port, serving this checkout's lab/ (not the one
// compiled into the program, which may be another checkout's): {server, url}.
export function startServer() {
  const server = spawn(bin, ['serve', '--port', '0', '--records', records, '--lab', join(repo, 'lab')],
    { stdio: ['ignore', 'pipe', 'pipe'] });
  let err = '';
  server.stderr.on('data', (d) => { err += d; });
  return new Promise((ok, fail) => {
    let out = '';
    server.stdout.on('data', (d) => {
      out += d;
      const m = out.match(/http:\/\/127\.0\.0\.1:(\d+)\//);
      if (m) ok({ server, url: m[0] });
    });
    server.on('error', (e) => fail(new Error(`rocking serve (${bin}) did not start: ${e.message}`)));
    server.on('exit', (code) => fail(new Error(`rocking serve exited (${code}): ${err}`)));
  });
}

// Headless Chromium (root needs --no-sandbox; puppeteer-core downloads no browser).
export async function launchBrowser() {
  const puppeteer = (await import('puppeteer-core')).default;
  return puppeteer.launch({
    executablePath: chromium, headless: true, args: ['--no-sandbox', '--disable-gpu', '--disable-dev-shm-usage'],
  });
}

// Waits until the page has made more than `runs` runs and none is in flight.
export const settled = (page, runs, timeout = 60000) => page.waitForFunction(
  (n) => window.lab && window.lab.runs > n && !window.lab.busy, { timeout }, runs);
export const runsOf = (page) => page.evaluate(() => window.lab.runs);

// Sets a control's value as a user's move does (an input event) and waits for its run.
export async function move(page, id, value) {
  const n = await runsOf(page);
  await page.$eval(`#${id}`, (e, v) => {
    if (e.type === 'checkbox') e.checked = v;
    else e.value = v;
    e.dispatchEvent(new Event('input', { bubbles: true }));
  }, value);
  await settled(page, n);
}

// Chooses an option of a list (a change of scene, record or twin) and waits for its run.
export async function choose(page, id, value) {
  const n = await runsOf(page);
  await page.select(`#${id}`, value);
  await settled(page, n);
}
