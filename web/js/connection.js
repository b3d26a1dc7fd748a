// One WebSocket session with reconnection. Opens /api/v1/ws, sends hello (built
// fresh by the page for every attempt, so a reconnect restores the current
// dataset, camera and parameters), routes server messages, and after a lost
// connection retries with a short back-off (0.5 s, 1 s, then every 1.5 s, with
// ±20 % jitter): a daemon that restarts is found within 2 s, and one probe a
// second and a half costs the server nothing. Errors the server marks fatal, and refusals that retrying cannot fix
// (unauthorized, unknown dataset), stop the retries until the page asks again.

import { parseServerMessage, unpackFrame, encodeMessage, ProtocolError } from './protocol.js';

export const BACKOFF_MIN_MS = 500;
export const BACKOFF_MAX_MS = 1500;

/** Delay before retry number attempt (0-based): min·2^attempt capped, ±20 % jitter. */
export function backoffDelay(attempt, random = Math.random) {
  const base = Math.min(BACKOFF_MAX_MS, BACKOFF_MIN_MS * 2 ** Math.min(attempt, 10));
  return Math.round(base * (0.8 + 0.4 * random()));
}

/** Error codes after which reconnecting with the same hello cannot succeed. */
export const TERMINAL_CODES = new Set([
  'unauthorized',
  'forbidden',
  'unknown_dataset',
  'not_found',
  'bad_field',
  'unknown_field',
  'missing_field',
  'out_of_range',
  'bad_json',
  'too_expensive',
]);

export class Connection {
  /**
   * url: ws:// URL of /api/v1/ws. hello(): returns the hello message object for
   * the next attempt. handlers: onReady(msg), onFrame({header, image}),
   * onError(msg, {fatal}), onStats(msg), onState(state, detail) where state is
   * 'connecting' | 'open' | 'waiting' (retry scheduled; detail.delay ms) |
   * 'stopped' (no retry; detail.reason). handlers.protocols(): optional, the
   * WebSocket subprotocols of the next attempt (they carry the token).
   */
  constructor(url, hello, handlers) {
    this.url = url;
    this.hello = hello;
    this.h = handlers;
    this.ws = null;
    this.attempt = 0;
    this.timer = null;
    this.stopped = true;
    this.ready = false;
    this.terminal = null; // error that ended the session for good
    this.bytesIn = 0;
  }

  /** Connects now (cancelling any scheduled retry) with a fresh hello. */
  start() {
    this.stopped = false;
    this.terminal = null;
    clearTimeout(this.timer);
    this.timer = null;
    this.#close();
    this.#open();
  }

  /** Closes and stops retrying. */
  stop(reason = 'closed') {
    this.stopped = true;
    clearTimeout(this.timer);
    this.timer = null;
    this.#close();
    this.h.onState?.('stopped', { reason });
  }

  /** Sends a client message object; false when not connected (the page keeps its state for the next hello). */
  send(msg) {
    if (!this.ws || this.ws.readyState !== WebSocket.OPEN || !this.ready) return false;
    this.ws.send(encodeMessage(msg));
    return true;
  }

  get isOpen() {
    return !!this.ws && this.ws.readyState === WebSocket.OPEN && this.ready;
  }

  #close() {
    if (!this.ws) return;
    const ws = this.ws;
    this.ws = null;
    this.ready = false;
    ws.onopen = ws.onmessage = ws.onclose = ws.onerror = null;
    try {
      ws.close(1000, 'client closed');
    } catch {
      /* already closing */
    }
  }

  #open() {
    this.h.onState?.('connecting', { attempt: this.attempt });
    let ws;
    try {
      const protocols = this.h.protocols?.() ?? [];
      ws = protocols.length ? new WebSocket(this.url, protocols) : new WebSocket(this.url);
    } catch (e) {
      this.#lost(`cannot open ${this.url}: ${e.message}`);
      return;
    }
    ws.binaryType = 'arraybuffer';
    this.ws = ws;
    ws.onopen = () => {
      try {
        ws.send(encodeMessage(this.hello()));
      } catch (e) {
        this.terminal = { code: e.code ?? 'bad_field', message: e.message };
        this.h.onError?.(this.terminal, { fatal: true });
        this.stop(e.message);
      }
    };
    ws.onmessage = (ev) => this.#message(ev.data);
    ws.onerror = () => {
      /* onclose follows with the code */
    };
    ws.onclose = (ev) => {
      if (this.ws !== ws) return;
      this.ws = null;
      this.ready = false;
      const why = ev.reason ? `${ev.reason} (code ${ev.code})` : `code ${ev.code}`;
      if (this.terminal) {
        this.stopped = true;
        this.h.onState?.('stopped', { reason: this.terminal.message, error: this.terminal });
      } else {
        this.#lost(ev.code === 1009 ? `message too large (${why})` : `connection closed (${why})`);
      }
    };
  }

  #lost(reason) {
    if (this.stopped) return;
    const delay = backoffDelay(this.attempt++);
    this.h.onState?.('waiting', { delay, reason, attempt: this.attempt });
    this.timer = setTimeout(() => {
      this.timer = null;
      if (!this.stopped) this.#open();
    }, delay);
  }

  #message(data) {
    if (typeof data !== 'string') {
      this.bytesIn += data.byteLength;
      let frame;
      try {
        frame = unpackFrame(data);
      } catch (e) {
        this.h.onError?.({ code: 'bad_frame', message: e.message }, { fatal: false });
        return;
      }
      frame.bytes = data.byteLength;
      this.h.onFrame?.(frame);
      return;
    }
    let msg;
    try {
      msg = parseServerMessage(data);
    } catch (e) {
      this.h.onError?.(
        { code: e instanceof ProtocolError ? e.code : 'bad_json', message: e.message },
        { fatal: false },
      );
      return;
    }
    if (msg.type === 'ready') {
      this.ready = true;
      this.attempt = 0;
      this.h.onState?.('open', {});
      this.h.onReady?.(msg);
    } else if (msg.type === 'error') {
      const fatal = msg.fatal === true || (!this.ready && TERMINAL_CODES.has(msg.code));
      if (fatal && TERMINAL_CODES.has(msg.code)) this.terminal = msg;
      this.h.onError?.(msg, { fatal });
      if (fatal) {
        try {
          this.ws?.close(1000, 'fatal error'); // the server closes too; onclose decides on a retry
        } catch {
          /* closing */
        }
      }
    } else if (msg.type === 'stats') {
      this.h.onStats?.(msg);
    } else if (msg.type === 'progress') {
      this.h.onProgress?.(msg);
    }
  }
}
