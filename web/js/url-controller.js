// The link: the page's dataset, camera and changes written into the URL hash
// (replaceState, so no history spam, 200 ms after the last change), and a
// pasted or edited link taken over as a fresh start.

import { parseHash, formatHash } from './url-state.js';
import { merge } from './schema.js';

export const HASH_DELAY_MS = 200;

/** ctx: state; location; history; setTimeout/clearTimeout (the page's timers). */
export function createUrlController(ctx) {
  const { state, location, history } = ctx;
  let timer = 0;
  let last = location.hash;

  function write() {
    timer = 0;
    // every value the user changed, even one equal to a default: ready.defaults already holds the hello's values;
    // and what the page chose where the user chose nothing (the contrasting background), which the picture
    // depends on as much: the link reproduces the picture wherever it is opened or turned into a render request
    const update = merge(state.pageDefaults ?? {}, state.update);
    const hash = formatHash({ dataset: state.dataset, camera: state.camera, update });
    if (hash !== location.hash)
      history.replaceState(history.state, '', `${location.pathname}${location.search}${hash}`);
    last = location.hash;
  }

  return {
    write,
    schedule() {
      ctx.clearTimeout(timer);
      timer = ctx.setTimeout(write, HASH_DELAY_MS);
    },
    /** On hashchange: the parsed link when someone else changed it (not this page's own write), else null. */
    taken() {
      if (location.hash === last) return null;
      const s = parseHash(location.hash);
      last = location.hash;
      return s;
    },
  };
}
