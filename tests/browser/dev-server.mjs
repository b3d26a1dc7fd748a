// Development helper: serves web/ from disk (no rebuild of the daemon after each
// edit) and forwards /api/*, /metrics and the WebSocket upgrade to a running
// daemon.   node tests/browser/dev-server.mjs [--port 8081] [--backend 127.0.0.1:8080]
//                                            [--generated BUILD/generated/web]
import http from 'node:http';
import net from 'node:net';
import { readFile } from 'node:fs/promises';
import { fileURLToPath } from 'node:url';
import path from 'node:path';

const arg = (name, dflt) => {
  const i = process.argv.indexOf(name);
  return i > 0 ? process.argv[i + 1] : dflt;
};
const port = Number(arg('--port', 8081));
const [bhost, bport] = arg('--backend', '127.0.0.1:8080').split(':');
const root = fileURLToPath(new URL('../../web/', import.meta.url));
// Modules the build generates (js/schema_fields.js) are served from the build tree.
const generated = path.resolve(
  arg('--generated', fileURLToPath(new URL('../../build/generated/web/', import.meta.url))),
);
const types = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript',
  '.css': 'text/css',
  '.svg': 'image/svg+xml',
  '.png': 'image/png',
};

const server = http.createServer(async (req, res) => {
  const url = new URL(req.url, 'http://x');
  if (url.pathname.startsWith('/api/') || url.pathname === '/metrics') {
    const up = http.request(
      { host: bhost, port: bport, method: req.method, path: req.url, headers: req.headers },
      (r) => {
        res.writeHead(r.statusCode, r.headers);
        r.pipe(res);
      },
    );
    up.on('error', (e) => {
      res.writeHead(502, { 'Content-Type': 'application/json' });
      res.end(JSON.stringify({ error: { code: 'unreachable', message: e.message } }));
    });
    req.pipe(up);
    return;
  }
  const rel = url.pathname === '/' ? 'index.html' : decodeURIComponent(url.pathname.slice(1));
  const file = path.join(root, rel);
  if (!file.startsWith(root) || rel.split('/').some((p) => p === 'test' || p === 'node_modules')) {
    res.writeHead(404).end();
    return;
  }
  try {
    const body = await readFile(file).catch(() => readFile(path.join(generated, rel)));
    res.writeHead(200, {
      'Content-Type': types[path.extname(file)] ?? 'application/octet-stream',
      'Cache-Control': 'no-cache',
    });
    res.end(body);
  } catch {
    res.writeHead(404).end('not found');
  }
});

server.on('upgrade', (req, socket, head) => {
  const up = net.connect(Number(bport), bhost, () => {
    const lines = [`${req.method} ${req.url} HTTP/1.1`];
    for (let i = 0; i < req.rawHeaders.length; i += 2) lines.push(`${req.rawHeaders[i]}: ${req.rawHeaders[i + 1]}`);
    up.write(`${lines.join('\r\n')}\r\n\r\n`);
    if (head?.length) up.write(head);
    up.pipe(socket);
    socket.pipe(up);
  });
  const end = () => {
    up.destroy();
    socket.destroy();
  };
  up.on('error', end);
  socket.on('error', end);
});

server.listen(port, '127.0.0.1', () => console.log(`dev server on http://127.0.0.1:${port}/ -> ${bhost}:${bport}`));
