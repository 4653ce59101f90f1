// Builds the animation page template: three.js and src/animation.js bundled
// and minified by esbuild into one classic script, inlined into src/page.html,
// written as a C++ raw string literal (OUTPUT, included by src/view/page.cpp).
// The C++ writer (src/view/animation.cpp) fills in the title, description,
// legend and data. Usage: node build.mjs OUTPUT
import { build } from 'esbuild';
import { readFileSync, writeFileSync, renameSync } from 'node:fs';
import { fileURLToPath } from 'node:url';
import { dirname, join } from 'node:path';

const here = dirname(fileURLToPath(import.meta.url));
const out = process.argv[2];
if (!out) throw new Error('usage: node build.mjs OUTPUT');
const result = await build({
  entryPoints: [join(here, 'src/animation.js')],
  bundle: true, minify: true, format: 'iife', target: 'es2020', write: false, legalComments: 'inline',
  logLevel: 'warning',
});
const script = result.outputFiles[0].text;
if (/<\/script/i.test(script) || script.includes('<!--')) throw new Error('bundled script contains </script or <!--');
const page = readFileSync(join(here, 'src/page.html'), 'utf8').replace('<!--LAGRANGIAN-SCRIPT-->', () => script);
const delimiter = 'lgvpage';
if (page.includes(')' + delimiter + '"')) throw new Error('the page contains the raw string delimiter');
writeFileSync(out + '.partial', `R"${delimiter}(${page})${delimiter}"\n`);
renameSync(out + '.partial', out);
console.log(`animation page template: ${out} (${(page.length / 1024).toFixed(0)} KiB)`);
