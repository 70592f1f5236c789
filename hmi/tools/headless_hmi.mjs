// Opens the HMI for some stations in headless Chromium and keeps it open until SIGINT/SIGTERM:
// a driver's screen for runs without a person in front of it. With --trace the pages report
// the receipt of every LCRW warning (hmi/src/trace.js), so that scripts/report can measure the
// hop from the broker to the HMI (the e2e latency test does).
//
//   node hmi/tools/headless_hmi.mjs --url http://127.0.0.1:9001/ --station 1001 [--station N]... [--trace]
//
// Prints "hmi: station N connected (URL) at T ms" (T: Unix ms) per page once its broker
// connection is up, the page's
// script errors as they happen, and one line per road event the page lists (#denm-list, read
// from the page's DOM every 200 ms), when it first appears and again when it is shown ended:
//   hmi: station N road event: from station X cause C seq S [sent by this station] [(ended)]
// Exits 1 when Chromium or a page cannot start.
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { parseArgs } from 'node:util';

import { chromium } from 'playwright-core';

const CHROMIUM = process.env.CHROMIUM ?? '/usr/bin/chromium';

const { values } = parseArgs({
  options: {
    url: { type: 'string', default: 'http://127.0.0.1:9001/' },
    station: { type: 'string', multiple: true, default: [] },
    trace: { type: 'boolean', default: false },
  },
});
if (values.station.length === 0 || values.station.some((s) => !/^\d+$/.test(s))) {
  console.error(`headless_hmi: --station takes a station id (got ${JSON.stringify(values.station)})`);
  process.exit(2);
}

// The road events a page lists, as its DOM shows them (hmi/src/main.js renderDenms).
async function printRoadEvents() {
  for (const p of pages) {
    let events;
    try {
      events = await p.page.$$eval('#denm-list li[data-originator]', (lis) => lis.map((li) => ({
        originator: li.dataset.originator,
        seq: li.dataset.seq,
        cause: li.dataset.cause,
        own: li.dataset.direction === 'out',
        ended: li.classList.contains('terminated'),
      })));
    } catch {
      continue; // the page is closing
    }
    for (const e of events) {
      const key = `${e.originator}/${e.seq}/${e.ended}`;
      if (!p.printed.has(key)) {
        p.printed.add(key);
        console.log(`hmi: station ${p.station} road event: from station ${e.originator} cause ${e.cause} seq ${e.seq}` +
          `${e.own ? ' sent by this station' : ''}${e.ended ? ' (ended)' : ''}`);
      }
    }
  }
}

const pages = [];
const userData = mkdtempSync(join(tmpdir(), 'hmi-headless-'));
let context = null;
let stopping = false;

async function stop(code) {
  if (stopping) {
    return;
  }
  stopping = true;
  await context?.close().catch(() => {});
  rmSync(userData, { recursive: true, force: true });
  process.exit(code);
}
process.on('SIGINT', () => stop(0));
process.on('SIGTERM', () => stop(0));

try {
  context = await chromium.launchPersistentContext(userData, {
    executablePath: CHROMIUM,
    headless: true,
    viewport: { width: 1100, height: 760 },
    // The flags the machine's notes give for a closed network (no background connections).
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  for (const station of values.station) {
    const page = await context.newPage();
    page.on('pageerror', (e) => console.error(`hmi: station ${station}: page error: ${e}`));
    const url = new URL(values.url);
    url.searchParams.set('station', station);
    if (values.trace) {
      url.searchParams.set('trace', '1');
    }
    await page.goto(url.toString());
    await page.waitForSelector('#conn[data-state="connected"]', { timeout: 20000 });
    console.log(`hmi: station ${station} connected (${url}) at ${Date.now()} ms`);
    pages.push({ station, page, printed: new Set() });
  }
  // One look at a time: the next one 200 ms after the last ended.
  const poll = async () => {
    await printRoadEvents();
    if (!stopping) {
      setTimeout(poll, 200);
    }
  };
  poll();
} catch (e) {
  console.error(`headless_hmi: ${e.message ?? e}`);
  await stop(1);
}
