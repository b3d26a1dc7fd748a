// The canvas: decodes each JPEG frame off the main thread (createImageBitmap)
// and draws only the newest. At most one decode runs at a time; a frame that
// arrives meanwhile waits in a one-slot mailbox, and a newer arrival replaces it
// (the replaced one is acknowledged as dropped). Every frame is acknowledged
// once it is drawn or dropped, so the server's window of unacknowledged frames
// follows what the page can actually show.

export class FrameView {
  /**
   * canvas: the <canvas>; ack(frameId) sends the acknowledgement; onDrawn(frame)
   * is told after a frame is on screen ({header, bytes, receivedAt, drawnAt}).
   */
  constructor(canvas, { ack, onDrawn, onError }) {
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
  }

  /** Forgets the previous session's frames (ids start again in a new session). */
  reset() {
    this.generation++;
    this.decoding = null;
    this.waiting = null;
    this.lastDrawn = -1;
  }

  /** Sets the canvas's backing store to the viewport in device pixels. */
  setSize(width, height) {
    if (this.canvas.width !== width || this.canvas.height !== height) {
      // keep the old picture while the next frame is on its way
      let keep = null;
      if (this.canvas.width > 0 && this.canvas.height > 0 && this.drawn > 0) {
        keep = document.createElement('canvas');
        keep.width = this.canvas.width;
        keep.height = this.canvas.height;
        keep.getContext('2d').drawImage(this.canvas, 0, 0);
      }
      this.canvas.width = width;
      this.canvas.height = height;
      if (keep) this.ctx.drawImage(keep, 0, 0, width, height);
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
      this.ctx.drawImage(bitmap, 0, 0, this.canvas.width, this.canvas.height);
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
