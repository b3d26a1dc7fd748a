// Edits of request fields (the panel, the legend's flip): into the page's
// state at once, to the server as one params message per animation frame.

import { paramsMessage } from './protocol.js';
import { setPath, merge, applicableUpdate } from './schema.js';
import { attributeRange } from './ui.js';
import { currentValues } from './app-state.js';

/**
 * ctx: state; send(msg) → false when the socket is closed; frame(fn) (requestAnimationFrame);
 * setCameraField(path, value) for camera.* paths; changed() after every edit (panel, link);
 * sent() after each message; toast(text) for a refused message.
 */
export function createParamsController(ctx) {
  const { state } = ctx;
  let pending = null;
  let frame = 0;

  function flush() {
    frame = 0;
    if (!pending) return;
    const update = pending;
    pending = null;
    try {
      const msg = paramsMessage(update);
      if (!ctx.send(msg)) return; // the next hello carries state.update
      ctx.sent?.();
    } catch (e) {
      ctx.toast(e.message);
    }
  }

  /** One edit of a request field: to the page's state, the server and the URL. */
  function applyChange(path, value) {
    if (path.startsWith('camera.')) {
      ctx.setCameraField(path, value);
      return;
    }
    const change = {};
    setPath(change, path, value);
    // a new attribute brings its own range, sent and written into the link (the previous
    // attribute's range would not fit, and the server would keep it); importance is [0, 1]
    if (path === 'importance.attribute' || path === 'color.attribute') {
      const section = path.split('.')[0];
      let r =
        value === 'importance' && section === 'color'
          ? [0, 1]
          : attributeRange(state.info, value, currentValues(state).params?.normalize);
      if (r && r[0] === r[1]) r = [r[0] - 0.5, r[1] + 0.5];
      if (r) setPath(change, `${section}.range`, r);
      else if (state.update[section]) delete state.update[section].range;
    }
    state.update = merge(state.update, change);
    pending = merge(pending ?? {}, change);
    // a new method (or opacity source): the fields kept in the page's state that apply again go with it
    if (path === 'method' || path === 'params.alphaSource')
      pending = merge(
        pending,
        applicableUpdate(state.update, state.update.layers?.length ? null : (state.info?.type ?? null)),
      );
    if (!frame) frame = ctx.frame(flush);
    ctx.changed();
  }

  return {
    applyChange,
    flush,
    /** A hello carries state.update: nothing is left to send. */
    drop() {
      pending = null;
    },
    get pending() {
      return pending;
    },
  };
}
