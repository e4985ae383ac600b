#!/usr/bin/env node
// Bundles src/extension.ts and its dependencies (vscode-languageclient) into dist/extension.js
// with esbuild; `vscode` is provided by the editor at run time.
//   node scripts/build.mjs            # one build (minified, with a source map)
//   node scripts/build.mjs --watch    # rebuild on change
import * as esbuild from 'esbuild';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const root = join(dirname(fileURLToPath(import.meta.url)), '..');
const watch = process.argv.includes('--watch');

const options = {
  absWorkingDir: root,
  entryPoints: ['src/extension.ts'],
  outfile: 'dist/extension.js',
  bundle: true,
  platform: 'node',
  format: 'cjs',
  target: 'node18',
  external: ['vscode'],
  minify: !watch,
  sourcemap: true,
  sourcesContent: false,
  logLevel: 'info',
};

if (watch) {
  const ctx = await esbuild.context(options);
  await ctx.watch();
} else {
  await esbuild.build(options);
}
