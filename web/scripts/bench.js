// Runs the benchmark page (bench.html) in headless Chromium on its WebGPU adapter (SwiftShader
// here) and prints the report's tables; `--json FILE` also writes the report. Every other
// `--name value` is a field of bench()'s configuration, as in the page's URL:
//   node scripts/bench.js --faces 10,100,1000 --levels 64,128 --frames 5 --json fig7.json
import { writeFileSync, renameSync } from 'node:fs';
import { start } from '../test/harness.js';

const args = process.argv.slice(2);
const query = new URLSearchParams();
let json = null;
for (let i = 0; i < args.length; i += 2) {
  const [key, value] = [args[i], args[i + 1]];
  if (!key.startsWith('--') || value === undefined) {
    console.error(`usage: node scripts/bench.js [--json FILE] [--FIELD VALUE]... (bad argument ${JSON.stringify(key)})`);
    process.exit(2);
  }
  if (key === '--json') json = value;
  else if (key !== '--run') query.set(key.slice(2), value); // this script runs it, once
}

const env = await start({ webgpu: true });
let failed = false;
try {
  const page = await env.browser.newPage();
  page.on('pageerror', (e) => console.error(`page error: ${e.message}`));
  await page.goto(`${env.url}bench.html?${query}`);
  await page.waitForFunction(() => window.bench !== undefined && window.bench.ready !== null);
  await page.evaluate(() => window.bench.ready);
  const report = await page.evaluate(() => window.bench.run());
  console.log(report.markdown);
  if (json) {
    // Written beside, then renamed: never a half-written file.
    writeFileSync(`${json}.tmp`, JSON.stringify(report, null, 1) + '\n');
    renameSync(`${json}.tmp`, json);
    console.log(`wrote ${json}`);
  }
} catch (e) {
  console.error(`the benchmark failed: ${e instanceof Error ? e.message : String(e)}`);
  failed = true;
} finally {
  await env.close();
}
process.exit(failed ? 1 : 0);
