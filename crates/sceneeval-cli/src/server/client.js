// The client side of sceneeval's local page server (sceneeval-cli, src/server), served to
// every page at /sceneeval-api.js: requests to the page's API with the per-run token the
// server put into the page (<meta name="sceneeval-token">). Load it before the page's script.
"use strict";

const SCENEEVAL_TOKEN = document.querySelector('meta[name="sceneeval-token"]').content;

// `sceneevalApi(method, path, body, options)`: the response's JSON, or an Error with the
// server's message. `body` (optional) is sent as JSON; `options.keepalive` lets the request
// outlive the page (a save when the page is closed).
async function sceneevalApi(method, path, body, options) {
  const init = {
    method,
    headers: { "X-Sceneeval-Token": SCENEEVAL_TOKEN },
    keepalive: Boolean(options && options.keepalive),
  };
  if (body !== undefined) {
    init.headers["Content-Type"] = "application/json";
    init.body = JSON.stringify(body);
  }
  const response = await fetch(path, init);
  let data = null;
  try { data = await response.json(); } catch (_) { data = null; }
  if (!response.ok) {
    throw new Error((data && data.error) || ("HTTP " + response.status));
  }
  return data;
}

// `sceneevalBlobUrl(path)`: a `blob:` URL of what an API route of bytes answers (an image),
// fetched with the token, for an <img> to show (revoke it with URL.revokeObjectURL when done).
async function sceneevalBlobUrl(path) {
  const response = await fetch(path, { headers: { "X-Sceneeval-Token": SCENEEVAL_TOKEN } });
  if (!response.ok) {
    let data = null;
    try { data = await response.json(); } catch (_) { data = null; }
    throw new Error((data && data.error) || ("HTTP " + response.status));
  }
  return URL.createObjectURL(await response.blob());
}
