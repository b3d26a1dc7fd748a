// Mouse, touch and keyboard navigation in ParaView's conventions, on top of the
// pure camera math in camera.js. Left-drag rotates about the focal point,
// middle-drag or shift-drag pans, wheel and right-drag zoom (dolly); touch: one
// finger rotates, two fingers pan and pinch-zoom. Keys: arrows rotate (with
// Shift: pan), +/− zoom, R resets, H goes home (the dataset's suggested view),
// F toggles fullscreen, X/Y/Z look along +axis (Shift: −axis).
// Every change goes to onCamera(camera, {at}) with the input event's time stamp;
// the page merges them into one message per animation frame.

import { orbit, pan, dolly, dragDollyFactor, wheelDollyFactor } from './camera.js';

const KEY_ROTATE_PX = 12; // an arrow key turns as far as a 12-pixel drag ...
const KEY_ZOOM = 1.15;

export class Navigation {
  /**
   * el: the focusable canvas. getCamera() returns the current camera (or null
   * before the first ready), onCamera(cam) applies a new one, onCommand(name)
   * runs 'reset', 'home', 'fullscreen' or an axis view ('+x', '-z', ...), onInteraction(active) tells
   * when a gesture starts and ends.
   */
  constructor(el, { getCamera, onCamera, onCommand, onInteraction }) {
    this.el = el;
    this.getCamera = getCamera;
    this.onCamera = onCamera;
    this.onCommand = onCommand;
    this.onInteraction = onInteraction ?? (() => {});
    this.pointers = new Map(); // pointerId -> {x, y, button}
    this.mode = null; // 'rotate' | 'pan' | 'zoom' | 'touch'
    this.pinch = null; // {dist, cx, cy}
    el.addEventListener('pointerdown', (e) => this.#down(e));
    el.addEventListener('pointermove', (e) => this.#move(e));
    el.addEventListener('pointerup', (e) => this.#up(e));
    el.addEventListener('pointercancel', (e) => this.#up(e));
    el.addEventListener('lostpointercapture', (e) => this.#up(e));
    el.addEventListener('wheel', (e) => this.#wheel(e), { passive: false });
    el.addEventListener('contextmenu', (e) => e.preventDefault());
    el.addEventListener('keydown', (e) => this.#key(e));
    el.style.touchAction = 'none';
  }

  get size() {
    const r = this.el.getBoundingClientRect();
    return [Math.max(r.width, 1), Math.max(r.height, 1)];
  }

  #apply(fn, e) {
    const cam = this.getCamera();
    if (!cam) return;
    this.onCamera(fn(cam), { at: e?.timeStamp });
  }

  #down(e) {
    if (!this.getCamera()) return;
    this.el.focus({ preventScroll: true });
    try {
      this.el.setPointerCapture(e.pointerId);
    } catch {
      /* synthetic events */
    }
    e.preventDefault();
    this.pointers.set(e.pointerId, { x: e.clientX, y: e.clientY });
    if (e.pointerType === 'touch') {
      this.mode = 'touch';
      this.pinch = this.pointers.size >= 2 ? this.#pinchState() : null;
    } else if (e.button === 1 || (e.button === 0 && e.shiftKey)) this.mode = 'pan';
    else if (e.button === 2 || (e.button === 0 && (e.ctrlKey || e.metaKey))) this.mode = 'zoom';
    else if (e.button === 0) this.mode = 'rotate';
    if (this.pointers.size === 1) this.onInteraction(true);
  }

  #pinchState() {
    const [a, b] = [...this.pointers.values()];
    return { dist: Math.hypot(a.x - b.x, a.y - b.y), cx: (a.x + b.x) / 2, cy: (a.y + b.y) / 2 };
  }

  #move(e) {
    const p = this.pointers.get(e.pointerId);
    if (!p) return;
    e.preventDefault();
    const dx = e.clientX - p.x,
      dy = e.clientY - p.y;
    if (this.mode === 'touch' && this.pointers.size >= 2) {
      p.x = e.clientX;
      p.y = e.clientY;
      const now = this.#pinchState();
      const before = this.pinch ?? now;
      const [w, h] = this.size;
      const factor = before.dist > 0 && now.dist > 0 ? now.dist / before.dist : 1;
      this.#apply((c) => dolly(pan(c, now.cx - before.cx, now.cy - before.cy, w, h), factor), e);
      this.pinch = now;
      return;
    }
    if (dx === 0 && dy === 0) return;
    p.x = e.clientX;
    p.y = e.clientY;
    const [w, h] = this.size;
    if (this.mode === 'rotate' || this.mode === 'touch') this.#apply((c) => orbit(c, dx, dy, w, h), e);
    else if (this.mode === 'pan') this.#apply((c) => pan(c, dx, dy, w, h), e);
    else if (this.mode === 'zoom') this.#apply((c) => dolly(c, dragDollyFactor(dy, h)), e);
  }

  #up(e) {
    if (!this.pointers.delete(e.pointerId)) return;
    if (this.pointers.size === 1 && this.mode === 'touch') this.pinch = null;
    if (this.pointers.size === 0) {
      this.mode = null;
      this.pinch = null;
      this.onInteraction(false);
    }
  }

  #wheel(e) {
    if (!this.getCamera()) return;
    e.preventDefault();
    // deltaMode 1 = lines, 2 = pages; bring both to pixels
    const dy = e.deltaY * (e.deltaMode === 1 ? 33 : e.deltaMode === 2 ? this.size[1] : 1);
    this.#apply((c) => dolly(c, wheelDollyFactor(Math.max(-500, Math.min(500, dy)))), e);
  }

  #key(e) {
    if (e.altKey || e.ctrlKey || e.metaKey) return;
    const [w, h] = this.size;
    const k = e.key;
    const step = KEY_ROTATE_PX;
    const arrows = { ArrowLeft: [-step, 0], ArrowRight: [step, 0], ArrowUp: [0, -step], ArrowDown: [0, step] };
    if (arrows[k]) {
      const [dx, dy] = arrows[k];
      this.#apply((c) => (e.shiftKey ? pan(c, dx, dy, w, h) : orbit(c, dx, dy, w, h)), e);
    } else if (k === '+' || k === '=' || k === 'PageUp') this.#apply((c) => dolly(c, KEY_ZOOM), e);
    else if (k === '-' || k === '_' || k === 'PageDown') this.#apply((c) => dolly(c, 1 / KEY_ZOOM), e);
    else if (k === 'r' || k === 'R') this.onCommand('reset');
    else if (k === 'h' || k === 'H') this.onCommand('home');
    else if (k === 'f' || k === 'F') this.onCommand('fullscreen');
    else if (/^[xyzXYZ]$/.test(k)) this.onCommand(`${e.shiftKey ? '-' : '+'}${k.toLowerCase()}`);
    else return;
    e.preventDefault();
  }
}
