// Frame statistics: frames per second, input → frame latency, the server's
// per-pass timings and encode time, bytes per frame, renderer and fading state.
// FrameStats is pure bookkeeping (tested in Node); renderStats writes the overlay.

export class FrameStats {
  constructor(now = () => performance.now()) {
    this.now = now;
    this.drawTimes = []; // timestamps of drawn frames in the last second
    this.sent = new Map(); // camera seq -> send time
    this.lastMeasuredSeq = 0;
    this.latency = null; // ms, input -> frame on screen
    this.latencyAvg = null;
    this.bytes = null;
    this.bytesAvg = null;
    this.header = null;
    this.frames = 0;
    this.server = {}; // last stats message
    this.renderer = '';
  }

  /** A camera message with this seq left now. */
  cameraSent(seq) {
    this.sent.set(seq, this.now());
    if (this.sent.size > 256) this.sent.delete(this.sent.keys().next().value);
  }

  /** A frame was drawn: header, byte size and the time it reached the screen. */
  frameDrawn(header, bytes, drawnAt = this.now()) {
    this.frames++;
    this.header = header;
    this.drawTimes.push(drawnAt);
    while (this.drawTimes.length && this.drawTimes[0] < drawnAt - 1000) this.drawTimes.shift();
    const ema = (old, v) => (old == null ? v : old * 0.8 + v * 0.2);
    this.bytes = bytes;
    this.bytesAvg = ema(this.bytesAvg, bytes);
    const seq = header.cameraSeq;
    if (typeof seq === 'number' && seq > this.lastMeasuredSeq && this.sent.has(seq)) {
      this.latency = drawnAt - this.sent.get(seq);
      this.latencyAvg = ema(this.latencyAvg, this.latency);
      this.lastMeasuredSeq = seq;
      for (const k of this.sent.keys()) if (k <= seq) this.sent.delete(k);
    }
  }

  /** Frames drawn in the last second (0 once frames stop for a second). */
  fps(at = this.now()) {
    const recent = this.drawTimes.filter((t) => t >= at - 1000);
    return recent.length;
  }

  /** The one-line readout shown by default: "12 fps · 85 ms". */
  summary(at = this.now()) {
    const lat = this.latencyAvg ?? this.latency;
    return `${this.fps(at)} fps · ${lat == null ? '– ms' : `${lat.toFixed(0)} ms`}`;
  }

  /** Lines of text for the overlay: [label, value] pairs. */
  lines(at = this.now()) {
    const out = [];
    const h = this.header;
    const ms = (v) => (v == null ? '–' : `${v.toFixed(v < 10 ? 1 : 0)} ms`);
    out.push(['fps', String(this.fps(at))]);
    out.push(['latency', this.latency == null ? '–' : `${ms(this.latency)} (avg ${ms(this.latencyAvg)})`]);
    if (h) {
      out.push(['frame', `#${h.frame} ${h.width}×${h.height} ${h.format}${h.quality ? ` q${h.quality}` : ''}`]);
      const t = h.timings && typeof h.timings === 'object' ? Object.entries(h.timings) : [];
      const total = t.reduce((s, [, v]) => s + v, 0);
      if (t.length) {
        out.push(['render', ms(total)]);
        for (const [pass, v] of t) out.push([`  ${pass}`, ms(v)]);
      }
      if (typeof h.encodeMs === 'number') out.push(['encode', ms(h.encodeMs)]);
      const d = h.detail;
      if (d && typeof d === 'object') {
        const parts = [d.interactive ? 'interactive' : 'still', `level ${d.level} (${d.lodPixels} px)`];
        if (d.pointStride > 1) parts.push(`every ${d.pointStride}th point`);
        if (d.lineStride > 1) parts.push(`1 in ${d.lineStride} of the less important lines`);
        if (d.reusedOpacities) parts.push('opacities reused');
        out.push(['detail', `${parts.join(', ')}; ${d.primitives} primitives`]);
      }
      out.push(['state', h.converged ? 'converged' : 'fading']);
      const v = visibilityText(h.visibility);
      if (v) out.push(['visibility', v]);
      const layers = Array.isArray(h.visibility?.layers) ? h.visibility.layers : [];
      layers.forEach((l, i) => {
        const lv = visibilityText(l);
        if (lv) out.push([`  layer ${i + 1}`, lv]);
      });
    }
    if (this.bytes != null) out.push(['bytes/frame', `${formatBytes(this.bytes)} (avg ${formatBytes(this.bytesAvg)})`]);
    if (this.renderer) out.push(['renderer', this.renderer]);
    const link = linkText(this.server);
    if (link) out.push(['link', link]);
    const have = new Set(out.map(([k]) => k));
    for (const [k, v] of Object.entries(this.server)) {
      if (k === 'type' || k === 'linkMbps' || k === 'linkMeasured' || v === null || typeof v === 'object') continue;
      out.push([have.has(k) ? `server ${k}` : k, typeof v === 'number' ? String(Number(v.toPrecision(4))) : String(v)]);
    }
    return out;
  }
}

/** The stats message's link estimate in words (null without one): the link's rate where frames waited on it
 * (what the moving frames' quality and size follow), else what it carried, a lower bound. */
export function linkText(s) {
  if (!s || typeof s.linkMbps !== 'number') return null;
  const v = Number(s.linkMbps.toPrecision(3));
  return s.linkMeasured ? `${v} Mbit/s (measured)` : `≥ ${v} Mbit/s (carried; no frame waited)`;
}

/** The frame's visibility report in words (null without one): what params.clarity aims at. */
export function visibilityText(v) {
  if (!v || typeof v.topDecileAlpha !== 'number') return null;
  const f = (x) => (typeof x === 'number' ? x.toFixed(2) : '–');
  const hidden =
    typeof v.importantOccluded === 'number'
      ? `; ${Math.round(100 * v.importantOccluded)}% of the important fragments hidden by importance`
      : '';
  // topDecileReach: the top tenth's share of the importance shown over its share of the importance drawn.
  const reach =
    typeof v.topDecileReach === 'number'
      ? `; the image shows the most important tenth ×${v.topDecileReach.toFixed(2)} ${v.topDecileReach < 1 ? '(behind the rest)' : '(in front of the rest)'}`
      : '';
  return `most important tenth ${f(v.topDecileAlpha)}, occluders ${f(v.occluderAlpha)}, least important half ${f(v.bottomHalfAlpha)} opaque${hidden}${reach}`;
}

/** Share of the important fragments with important mass in front above which the page warns (docs/ALGORITHM.md §8). */
export const IMPORTANT_OCCLUDED_WARN = 0.25;

/** The warning when important structures hide each other (OOS §7.2), '' otherwise: no opacity can show both. */
export function occlusionWarning(v) {
  const x = v?.importantOccluded;
  if (typeof x !== 'number' || !(x >= IMPORTANT_OCCLUDED_WARN)) return '';
  return (
    `${Math.round(100 * x)}% of the important fragments lie behind other important ones: ` +
    'no opacity can show both. Turn the view, or narrow the importance (filter, importance range).'
  );
}

/** params.clarity's outcome (frame header "clarity") in words: '' when the goal was met or the loop was off. */
export function clarityNote(c) {
  if (!c || c.reached !== false || typeof c.lambdaFactor !== 'number') return '';
  const smoothing = typeof c.smoothing === 'number' ? `, smoothing ${c.smoothing} iterations` : '';
  return (
    ` The goal is out of reach on these data: the optimization stopped at λ ×${c.lambdaFactor.toFixed(1)}, ` +
    `q and r ×${c.penaltyFactor.toFixed(1)}${smoothing}, the strength that came closest.`
  );
}

export function formatBytes(n) {
  if (n == null) return '–';
  if (n < 1024) return `${Math.round(n)} B`;
  if (n < 1024 * 1024) return `${(n / 1024).toFixed(1)} KiB`;
  return `${(n / 1024 / 1024).toFixed(2)} MiB`;
}

/** Writes the overlay (a definition list) into el. */
export function renderStats(el, stats) {
  const dl = document.createElement('dl');
  for (const [k, v] of stats.lines()) {
    const dt = document.createElement('dt');
    dt.textContent = k;
    const dd = document.createElement('dd');
    dd.textContent = v;
    if (k === 'state') dd.dataset.state = v;
    dl.append(dt, dd);
  }
  el.replaceChildren(dl);
}
