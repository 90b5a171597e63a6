// The TypeScript declarations type the API as the other tests use it (strict tsc, no emit):
// test/types/usage.ts compiles, and its @ts-expect-error lines are refused.
import { test } from 'node:test';
import assert from 'node:assert/strict';
import { execFileSync } from 'node:child_process';
import { fileURLToPath } from 'node:url';

test('the .d.ts files compile against a strict usage file', () => {
  const tsc = fileURLToPath(new URL('../node_modules/typescript/bin/tsc', import.meta.url));
  const project = fileURLToPath(new URL('./types/tsconfig.json', import.meta.url));
  const out = execFileSync(process.execPath, [tsc, '-p', project], { encoding: 'utf8' });
  assert.equal(out.trim(), '');
});
