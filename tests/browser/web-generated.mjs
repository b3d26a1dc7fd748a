// Lets Node load the page's modules that the build generates (web/js/schema_fields.js lives in
// BUILD/generated/web/, not in web/): `node --import tests/browser/web-generated.mjs ...` with
// LUCENT_WEB_GENERATED=BUILD/generated/web. A page import that web/ lacks resolves to that folder.
import { register } from 'node:module';

const dir = process.env.LUCENT_WEB_GENERATED;
if (!dir) throw new Error('web-generated.mjs: set LUCENT_WEB_GENERATED to BUILD/generated/web');
register(new URL('./web-generated-hooks.mjs', import.meta.url), {
  data: { web: new URL('../../web/', import.meta.url).href, generated: dir },
});
