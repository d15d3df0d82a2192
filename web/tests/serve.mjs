// A static file server on 127.0.0.1 (an ephemeral port) for the browser tests: the page
// needs http (not file:) for its module and fetches, and .wasm as application/wasm.
import { createServer } from 'node:http';
import { readFile } from 'node:fs/promises';
import { join, normalize, extname, relative, isAbsolute } from 'node:path';

const TYPES = {
  '.html': 'text/html', '.js': 'text/javascript', '.mjs': 'text/javascript', '.wasm': 'application/wasm',
  '.json': 'application/json', '.gltf': 'model/gltf+json', '.glb': 'model/gltf-binary', '.bin': 'application/octet-stream',
  '.png': 'image/png', '.jpg': 'image/jpeg', '.jpeg': 'image/jpeg', '.webp': 'image/webp', '.ktx2': 'image/ktx2',
  '.toml': 'text/plain',
};

/** Serves `folder`, and `extra` (path: body) before it. Resolves once listening. */
export function serveFolder(folder, extra = {}) {
  return serveMounts({ '/': folder }, extra);
}

/** Serves each folder of `mounts` (URL prefix ending in '/': folder), and `extra` (path:
 * body) before them. Resolves once listening. */
export function serveMounts(mounts, extra = {}) {
  const prefixes = Object.keys(mounts).sort((a, b) => b.length - a.length);
  const server = createServer(async (request, response) => {
    let path;
    try {
      path = decodeURIComponent(new URL(request.url, 'http://x').pathname);
    } catch {
      response.writeHead(400);
      return response.end();
    }
    if (path in extra) {
      response.writeHead(200, { 'content-type': TYPES[extname(path)] || 'application/octet-stream' });
      return response.end(extra[path]);
    }
    const prefix = prefixes.find((p) => path.startsWith(p));
    if (prefix === undefined) {
      response.writeHead(404);
      return response.end();
    }
    const folder = mounts[prefix];
    const file = normalize(join(folder, path.slice(prefix.length)));
    const inside = relative(folder, file);
    if (inside.startsWith('..') || isAbsolute(inside)) {
      response.writeHead(403);
      return response.end();
    }
    try {
      const body = await readFile(file);
      response.writeHead(200, { 'content-type': TYPES[extname(file)] || 'application/octet-stream' });
      response.end(body);
    } catch {
      response.writeHead(404, { 'content-type': 'text/plain' });
      response.end('not found');
    }
  });
  return new Promise((done) => server.listen(0, '127.0.0.1', () => done(server)));
}
