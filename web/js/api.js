// HTTP API calls (protocol/openapi.yaml): datasets, health and the PNG render
// behind the screenshot button. Failures become ApiError with the server's
// error code and a readable message.

import { describeError } from './protocol.js';

export class ApiError extends Error {
  constructor(status, code, message) {
    super(message);
    this.name = 'ApiError';
    this.status = status;
    this.code = code;
  }
}

async function failure(res) {
  let body = null;
  try {
    body = await res.json();
  } catch {
    /* not JSON */
  }
  const code = body?.error?.code ?? (res.status === 401 ? 'unauthorized' : `http_${res.status}`);
  const msg = body?.error ? describeError(body) : `${res.status} ${res.statusText || 'error'}`;
  return new ApiError(res.status, code, msg);
}

export class Api {
  /** base: URL of the server root; token(): the current token or null. */
  constructor(base, token) {
    this.base = base;
    this.token = token;
  }

  #headers(extra = {}) {
    const t = this.token();
    return t ? { ...extra, Authorization: `Bearer ${t}` } : extra;
  }

  async #get(path) {
    let res;
    try {
      res = await fetch(new URL(path, this.base), { headers: this.#headers(), cache: 'no-store' });
    } catch (e) {
      throw new ApiError(0, 'unreachable', `The server cannot be reached (${e.message}).`);
    }
    if (!res.ok) throw await failure(res);
    return res.json();
  }

  /** The dataset descriptions: an array of {name, ...} whatever the body's wrapper. */
  /** The datasets, then the vector fields (kind "field": a request on one draws a traced streamline set). */
  async datasets() {
    const body = await this.#get('api/v1/datasets');
    const list = Array.isArray(body) ? body : Array.isArray(body?.datasets) ? body.datasets : [];
    const fields = Array.isArray(body?.fields) ? body.fields.map((f) => ({ ...f, kind: 'field' })) : [];
    return [...list, ...fields];
  }

  /** The vector fields (GET /api/v1/datasets "fields"): an array of {name, bounds, ...}. */
  async fields() {
    const body = await this.#get('api/v1/datasets');
    return Array.isArray(body?.fields) ? body.fields : [];
  }

  health() {
    return this.#get('api/v1/health');
  }

  /** POST /api/v1/render; returns {blob, timings} (timings header text, if any). */
  async render(request) {
    let res;
    try {
      res = await fetch(new URL('api/v1/render', this.base), {
        method: 'POST',
        headers: this.#headers({ 'Content-Type': 'application/json' }),
        body: JSON.stringify(request),
      });
    } catch (e) {
      throw new ApiError(0, 'unreachable', `The server cannot be reached (${e.message}).`);
    }
    if (!res.ok) throw await failure(res);
    return { blob: await res.blob(), timings: res.headers.get('X-Lucent-Timings') ?? res.headers.get('Server-Timing') };
  }

  /** POST /api/v1/movies (protocol/README.md "Movies"); returns the job ({id, state, progress, ...}). */
  async createMovie(body) {
    let res;
    try {
      res = await fetch(new URL('api/v1/movies', this.base), {
        method: 'POST',
        headers: this.#headers({ 'Content-Type': 'application/json' }),
        body: JSON.stringify(body),
      });
    } catch (e) {
      throw new ApiError(0, 'unreachable', `The server cannot be reached (${e.message}).`);
    }
    if (!res.ok) throw await failure(res);
    return res.json();
  }

  /** GET /api/v1/movies/ID: the job's state and progress. */
  movie(id) {
    return this.#get(`api/v1/movies/${encodeURIComponent(id)}`);
  }

  /** The link that downloads a finished movie (the token rides in the query, as for <img> renders). */
  movieFileUrl(id) {
    const url = new URL(`api/v1/movies/${encodeURIComponent(id)}/file`, this.base);
    const t = this.token();
    if (t) url.searchParams.set('token', t);
    return url.href;
  }
}
