// The raypack preview page: the controls, the canvas and the results. The
// rendering runs in worker.js (a Web Worker), band by band; this module
// only draws the bands it receives, so the page never waits on a render.
//
// State for scripts (the browser test reads it): document.body.dataset.state
// is 'loading', 'idle', 'rendering', 'done' or 'error', and window.raypackLast
// holds the last render's figures.

const $ = (id) => document.getElementById(id);
const hex = (v) => '0x' + (v >>> 0).toString(16).padStart(8, '0');

// FNV-1a 32 (the checksum of targets/checksums.txt), over bytes.
function fnv1a(bytes, h = 0x811c9dc5) {
  for (let i = 0; i < bytes.length; i++) h = Math.imul(h ^ bytes[i], 0x01000193) >>> 0;
  return h >>> 0;
}

let worker = null;
let workerReady = null;
let nextId = 1;
let current = null; // the render in progress or last finished
const sceneCache = new Map();
let fileScene = null; // {name, bytes} of a file picked or dropped

function startWorker() {
  if (worker) worker.terminate();
  worker = new Worker('worker.js');
  workerReady = new Promise((resolve, reject) => {
    worker.onmessage = (event) => {
      const m = event.data;
      if (m.type === 'ready') {
        worker.onmessage = onWorkerMessage;
        resolve(m);
      } else {
        reject(new Error(m.message));
      }
    };
    worker.onerror = (e) => reject(new Error(`worker: ${e.message}`));
  });
  return workerReady;
}

function setState(state) {
  document.body.dataset.state = state;
}

function showError(text) {
  $('error').textContent = text;
}

// The scene chosen, as {name, demo} or {name, bytes}; name is what the
// command line would print (the file's name; 'standard input' for text).
async function chosenScene() {
  const choice = $('scene').value;
  if (choice === 'demo') return { name: 'demo scene', demo: true };
  if (choice === 'paste') return { name: 'standard input', bytes: new TextEncoder().encode($('text').value).buffer };
  if (choice === 'file') {
    if (!fileScene) throw new Error('choose or drop an .nff file first');
    return { name: fileScene.name, bytes: fileScene.bytes.slice(0) };
  }
  if (!sceneCache.has(choice)) {
    const response = await fetch(`scenes/${choice}.nff`);
    if (!response.ok) throw new Error(`scenes/${choice}.nff: HTTP ${response.status}`);
    sceneCache.set(choice, await response.arrayBuffer());
  }
  return { name: `${choice}.nff`, bytes: sceneCache.get(choice).slice(0) };
}

function numberOrZero(input) {
  const v = parseInt(input.value, 10);
  return Number.isFinite(v) && v > 0 ? v : 0;
}

async function render() {
  if (current && !current.finished) {
    // A render is running: stop it (a fresh worker) and start this one.
    current.finished = true;
    startWorker();
  }
  const id = nextId++;
  const job = {
    id, scalar: +$('scalar').value, width: numberOrZero($('width')), height: numberOrZero($('height')),
    packet: +$('packet').value, aov: +$('aov').value, output: +$('output').value, bandRows: 8,
  };
  current = { id, job, finished: false, bands: 0, progressAt: [], started: performance.now() };
  window.raypackLast = current;
  setState('rendering');
  showError('');
  $('progress').value = 0;
  $('bands').textContent = '';
  for (const k of ['time', 'rays', 'raysps', 'checksum', 'rgb888', 'rgb565', 'load', 'size']) $(k).textContent = '';
  $('save-png').disabled = $('save-stream').disabled = true;
  try {
    const scene = await chosenScene();
    current.name = scene.name;
    await workerReady;
    if (current.id !== id) return;
    job.scene = scene.demo ? { demo: true } : { bytes: scene.bytes };
    worker.postMessage(job, scene.demo ? [] : [scene.bytes]);
  } catch (e) {
    finishWithError(id, `${e.message || e}`);
  }
}

function finishWithError(id, text) {
  if (!current || current.id !== id) return;
  current.finished = true;
  current.error = text;
  showError(text);
  setState('error');
}

function onWorkerMessage(event) {
  const m = event.data;
  if (!current || m.id !== current.id) return;
  const c = current;
  if (m.type === 'error') {
    // The command line's line: `raypack: error: FILE: MESSAGE`.
    finishWithError(m.id, `raypack: error: ${c.name}: ${m.message}`);
    if (m.fatal) startWorker();
  } else if (m.type === 'setup') {
    Object.assign(c, { width: m.width, height: m.height, packet: m.packet, primitives: m.primitives, loadMs: m.loadMs });
    const canvas = $('image');
    canvas.width = m.width;
    canvas.height = m.height;
    applyZoom();
    c.stream = new Uint8Array(m.width * m.height * (c.job.output === 1 ? 2 : 3));
    c.streamAt = 0;
    c.totalBands = Math.ceil(m.height / c.job.bandRows);
    $('size').textContent = `${m.width}×${m.height}, packet ${m.packet}` +
      (m.packet !== c.job.packet ? ' (fixed point traces one ray per packet)' : '') + `, ${m.primitives} primitives`;
    $('load').textContent = `${m.loadMs.toFixed(1)} ms`;
  } else if (m.type === 'band') {
    const ctx = $('image').getContext('2d');
    ctx.putImageData(new ImageData(m.rgba, c.width, m.rows), 0, m.y);
    c.stream.set(m.stream, c.streamAt);
    c.streamAt += m.stream.length;
    c.bands += 1;
    c.progressAt.push(performance.now());
    $('progress').value = (m.y + m.rows) / c.height;
    $('bands').textContent = `band ${c.bands} of ${c.totalBands}`;
  } else if (m.type === 'done') {
    c.finished = true;
    Object.assign(c, { ms: m.ms, rays: m.rays, rgb888: hex(m.rgb888), rgb565: hex(m.rgb565) });
    // The checksum of the bytes this page received (the output stream).
    c.streamFnv = hex(fnv1a(c.stream.subarray(0, c.streamAt)));
    c.doneAt = performance.now();
    const [primary, shadow, reflected, refracted, total] = m.rays;
    $('time').textContent = `${m.ms.toFixed(1)} ms`;
    $('rays').textContent = `${total} (${primary} primary, ${shadow} shadow, ${reflected} reflected, ${refracted} refracted)`;
    $('raysps').textContent = m.ms > 0 ? `${(total / m.ms / 1e3).toFixed(2)} M rays/s` : '';
    $('rgb888').textContent = c.rgb888;
    $('rgb565').textContent = c.rgb565;
    $('checksum').textContent = `${c.job.output === 1 ? c.rgb565 + ' (RGB565)' : c.rgb888 + ' (RGB888)'}`;
    $('save-png').disabled = $('save-stream').disabled = false;
    setState('done');
  }
}

function applyZoom() {
  const canvas = $('image');
  const zoom = +$('zoom').value;
  canvas.style.width = `${canvas.width * zoom}px`;
  canvas.style.height = `${canvas.height * zoom}px`;
}

function download(blob, name) {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(blob);
  a.download = name;
  a.click();
  setTimeout(() => URL.revokeObjectURL(a.href), 1000);
}

function stem() {
  return (current && current.name ? current.name : 'raypack').replace(/\.nff$/, '').replace(/[^\w.-]+/g, '-');
}

async function useFile(file) {
  fileScene = { name: file.name, bytes: await file.arrayBuffer() };
  let option = document.querySelector('#scene option[value=file]');
  option.textContent = `file: ${file.name}`;
  $('scene').value = 'file';
  sceneChanged();
}

function sceneChanged() {
  $('paste').style.display = $('scene').value === 'paste' ? 'block' : 'none';
}

async function init() {
  try {
    const response = await fetch('scenes/index.json');
    const names = response.ok ? await response.json() : [];
    const select = $('scene');
    for (const name of names) select.add(new Option(`${name} (SPD)`, name));
    select.add(new Option('file: none chosen', 'file'));
    select.add(new Option('pasted NFF text', 'paste'));
  } catch (e) {
    showError(`scenes/index.json: ${e}`);
  }
  $('scene').addEventListener('change', sceneChanged);
  $('zoom').addEventListener('change', applyZoom);
  $('render').addEventListener('click', render);
  $('file').addEventListener('change', () => $('file').files[0] && useFile($('file').files[0]));
  const drop = document.documentElement;
  drop.addEventListener('dragover', (e) => { e.preventDefault(); $('drop').classList.add('over'); });
  drop.addEventListener('dragleave', () => $('drop').classList.remove('over'));
  drop.addEventListener('drop', (e) => {
    e.preventDefault();
    $('drop').classList.remove('over');
    if (e.dataTransfer.files[0]) useFile(e.dataTransfer.files[0]);
  });
  $('save-png').addEventListener('click', () => $('image').toBlob((b) => download(b, `${stem()}.png`)));
  $('save-stream').addEventListener('click', () => {
    const c = current;
    const kind = c.job.output === 1 ? 'rgb565be' : 'rgb888';
    download(new Blob([c.stream.subarray(0, c.streamAt)]), `${stem()}-${c.width}x${c.height}.${kind}`);
  });
  try {
    await startWorker();
    setState('idle');
    render(); // the demo scene at the firmware's size
  } catch (e) {
    showError(`${e.message || e}`);
    setState('error');
  }
}

init();
