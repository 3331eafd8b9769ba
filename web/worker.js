// The render worker of the raypack preview: loads raypack_web.wasm (the
// no_std core, WebAssembly SIMD) and renders band by band, posting each
// band as it is done, so the page stays responsive and shows progress.
//
// Messages in:  {id, scene: {demo: true} | {bytes: ArrayBuffer}, scalar: 0|1,
//                width, height (0: the scene's), packet: 1|4, aov: 0..3,
//                output: 0 (RGB888) | 1 (RGB565), bandRows}
// Messages out: {type: 'ready', wasmBytes}
//               {type: 'setup', id, width, height, packet, primitives, loadMs}
//               {type: 'band', id, y, rows, rgba, stream}   (transferred buffers)
//               {type: 'done', id, ms, rays: [primary, shadow, reflected, refracted, total], rgb888, rgb565}
//               {type: 'error', id, message}
'use strict';

let wasm = null;
const ready = (async () => {
  const response = await fetch('raypack_web.wasm');
  if (!response.ok) throw new Error(`raypack_web.wasm: HTTP ${response.status}`);
  const bytes = await response.arrayBuffer();
  // The module imports nothing (scripts/web.sh checks it).
  const { instance } = await WebAssembly.instantiate(bytes, {});
  wasm = instance.exports;
  postMessage({ type: 'ready', wasmBytes: bytes.byteLength });
})().catch((e) => postMessage({ type: 'error', id: -1, message: `cannot load the WebAssembly module: ${e}` }));

function message() {
  const ptr = wasm.rp_message();
  const len = wasm.rp_message_len();
  return new TextDecoder().decode(new Uint8Array(wasm.memory.buffer, ptr, len));
}

// Loads the scene and sets up the render; returns false (after posting the
// error) if either fails.
function setup(job) {
  const t0 = performance.now();
  let status;
  if (job.scene.demo) {
    status = wasm.rp_load_demo(job.scalar);
  } else {
    const bytes = new Uint8Array(job.scene.bytes);
    const ptr = wasm.rp_text_buffer(bytes.length);
    if (ptr === 0) {
      postMessage({ type: 'error', id: job.id, message: message() });
      return false;
    }
    new Uint8Array(wasm.memory.buffer, ptr, bytes.length).set(bytes);
    status = wasm.rp_load(bytes.length, job.scalar);
  }
  if (status === 0) status = wasm.rp_setup(job.width, job.height, job.packet, job.aov, job.output);
  if (status !== 0) {
    postMessage({ type: 'error', id: job.id, message: message() });
    return false;
  }
  postMessage({
    type: 'setup', id: job.id, width: wasm.rp_info(0), height: wasm.rp_info(1), packet: wasm.rp_info(2),
    primitives: wasm.rp_info(3), loadMs: performance.now() - t0,
  });
  return true;
}

function render(job) {
  if (!setup(job)) return;
  const width = wasm.rp_info(0);
  let ms = 0;
  for (;;) {
    // Only the band calls are timed: the render time the page shows.
    const t0 = performance.now();
    const rows = wasm.rp_render_band(job.bandRows);
    ms += performance.now() - t0;
    if (rows < 0) {
      postMessage({ type: 'error', id: job.id, message: message() });
      return;
    }
    if (rows === 0) break;
    const rgba = new Uint8ClampedArray(wasm.memory.buffer, wasm.rp_rgba(), width * rows * 4).slice();
    const stream = new Uint8Array(wasm.memory.buffer, wasm.rp_stream(), wasm.rp_stream_len()).slice();
    postMessage({ type: 'band', id: job.id, y: wasm.rp_band_y(), rows, rgba, stream }, [rgba.buffer, stream.buffer]);
  }
  const rays = [0, 1, 2, 3, 4].map((k) => wasm.rp_rays(k));
  postMessage({
    type: 'done', id: job.id, ms, rays, rgb888: wasm.rp_checksum(0) >>> 0, rgb565: wasm.rp_checksum(1) >>> 0,
  });
}

onmessage = async (event) => {
  const job = event.data;
  try {
    await ready;
    if (!wasm) return;
    render(job);
  } catch (e) {
    // A trap (a bug: the module is built not to panic) or a JavaScript
    // error: reported, never silent. The page starts a fresh worker.
    postMessage({ type: 'error', id: job.id, message: `internal error: ${e}`, fatal: true });
  }
};
