// One script for a page, as both pages bundle theirs (report/build.mjs,
// webapp/build.mjs): `entry` with its imports (the viewer, three.js) by
// esbuild, minified, `define`'s names replaced, ready to go inside <script>.
import { build } from 'esbuild';

export async function bundleScript(entry, define = {}) {
  const bundle = await build({
    entryPoints: [entry],
    bundle: true,
    minify: true,
    format: 'iife',
    target: 'es2022',
    write: false,
    legalComments: 'inline',  // three.js's licence notice stays with its code
    logLevel: 'warning',
    define,
  });
  // Inside <script>, "</script" would end the element early.
  return bundle.outputFiles[0].text.replaceAll('</script', '<\\/script');
}
