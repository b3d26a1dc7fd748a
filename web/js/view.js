// The canvas: decodes each JPEG frame off the main thread (createImageBitmap)
// and draws only the newest. At most one decode runs at a time; a frame that
// arrives meanwhile waits in a one-slot mailbox, and a newer arrival replaces it
// (the replaced one is acknowledged as dropped). Every frame is acknowledged
// once it is drawn or dropped, so the server's window of unacknowledged frames
// follows what the page can actually show.
//
// Between frames the newest picture is redrawn for the current camera (an
// affine warp from warp.js), so navigation answers at once even when frames
// take a few hundred milliseconds: setCamera() repaints synchronously.

import { warpTransform } from './warp.js';

export class FrameView {
  /**
   * canvas: the <canvas>; ack(frameId) sends the acknowledgement; onDrawn(frame)
   * is told after a frame is on screen ({header, bytes, receivedAt, drawnAt}).
   * frameCamera(header) returns the camera a frame was rendered with (or null:
   * no warp); background() the CSS colour of the area a warp uncovers.
   */
  constructor(canvas, { ack, onDrawn, onError, frameCamera, background }) {
    this.canvas = canvas;
    this.ctx = canvas.getContext('2d', { alpha: false });
    this.ack = ack;
    this.onDrawn = onDrawn ?? (() => {});
    this.onError = onError ?? (() => {});
    this.decoding = null; // frame being decoded
    this.waiting = null; // newest frame that arrived during the decode
    this.lastDrawn = -1; // id of the newest frame on screen
    this.dropped = 0;
    this.drawn = 0;
    this.generation = 0; // bumped by reset(): a new session's frame ids restart
    this.frameCamera = frameCamera ?? (() => null);
    this.background = background ?? (() => '#000');
    this.bitmap = null; // the newest decoded frame, kept for warping
    this.bitmapCamera = null; // the camera it was rendered with
    this.camera = null; // the camera the page shows now
    this.warped = false; // whether the last paint used a transform
  }

  /** The page's camera changed: repaint the last frame warped toward it. Returns true when painted. */
  setCamera(cam) {
    this.camera = cam;
    return this.#paint();
  }

  #paint() {
    if (!this.bitmap) return false;
    const { width: w, height: h } = this.canvas;
    const m = this.bitmapCamera && this.camera ? warpTransform(this.bitmapCamera, this.camera, w, h) : null;
    const ctx = this.ctx;
    if (m) {
      ctx.fillStyle = this.background();
      ctx.fillRect(0, 0, w, h);
      ctx.setTransform(m[0], m[1], m[2], m[3], m[4], m[5]);
    }
    ctx.drawImage(this.bitmap, 0, 0, w, h);
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    this.warped = !!m;
    return true;
  }

  /** Forgets the previous session's frames (ids start again in a new session). */
  reset() {
    this.generation++;
    this.decoding = null;
    this.waiting = null;
    this.lastDrawn = -1;
  }

  /** Forgets the kept picture (a new dataset: the old one must not be warped into its view). */
  clear() {
    this.bitmap?.close();
    this.bitmap = null;
    this.bitmapCamera = null;
  }

  /** Sets the canvas's backing store to the viewport in device pixels. */
  setSize(width, height) {
    if (this.canvas.width !== width || this.canvas.height !== height) {
      // keep the old picture while the next frame is on its way
      let keep = null;
      if (!this.bitmap && this.canvas.width > 0 && this.canvas.height > 0 && this.drawn > 0) {
        keep = document.createElement('canvas');
        keep.width = this.canvas.width;
        keep.height = this.canvas.height;
        keep.getContext('2d').drawImage(this.canvas, 0, 0);
      }
      this.canvas.width = width;
      this.canvas.height = height;
      if (keep) this.ctx.drawImage(keep, 0, 0, width, height);
      else this.#paint();
    }
  }

  /** A frame arrived ({header, image: Uint8Array}). */
  push(frame) {
    frame.receivedAt = performance.now();
    frame.generation = this.generation;
    if (this.decoding) {
      if (this.waiting) this.#drop(this.waiting);
      this.waiting = frame;
      return;
    }
    this.#decode(frame);
  }

  #drop(frame) {
    this.dropped++;
    if (frame.generation === this.generation) this.ack(frame.header.frame);
  }

  async #decode(frame) {
    this.decoding = frame;
    const type = frame.header.format === 'png' ? 'image/png' : 'image/jpeg';
    let bitmap = null;
    try {
      bitmap = await createImageBitmap(new Blob([frame.image], { type }));
    } catch (e) {
      this.onError(new Error(`frame ${frame.header.frame} could not be decoded (${e.message})`));
    }
    const current = frame.generation === this.generation;
    if (bitmap && current && frame.header.frame > this.lastDrawn) {
      this.bitmap?.close();
      this.bitmap = bitmap;
      this.bitmapCamera = this.frameCamera(frame.header);
      bitmap = null; // kept
      this.#paint();
      this.lastDrawn = frame.header.frame;
      this.drawn++;
      frame.drawnAt = performance.now();
      this.ack(frame.header.frame);
      this.onDrawn(frame);
    } else if (current) {
      this.#drop(frame);
    }
    bitmap?.close();
    if (this.decoding !== frame) return; // reset() happened; the new session's decode owns the mailbox
    this.decoding = null;
    const next = this.waiting;
    this.waiting = null;
    if (next) this.#decode(next);
  }
}
