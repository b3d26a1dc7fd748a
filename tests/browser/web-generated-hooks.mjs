// Module resolution hooks registered by web-generated.mjs: an import under web/ whose file does
// not exist there is looked up in the build's generated copy of web/.
import { existsSync } from 'node:fs';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

let web, generated;

export function initialize(data) {
  web = data.web;
  generated = path.resolve(data.generated);
}

export async function resolve(specifier, context, next) {
  if (context.parentURL?.startsWith(web) && (specifier.startsWith('./') || specifier.startsWith('../'))) {
    const target = new URL(specifier, context.parentURL);
    if (target.href.startsWith(web) && !existsSync(fileURLToPath(target))) {
      const built = path.join(generated, target.href.slice(web.length));
      if (existsSync(built)) return { url: pathToFileURL(built).href, shortCircuit: true };
    }
  }
  return next(specifier, context);
}
