// The USD stage of a run (`pbf export usd`, `pbf run --usd`) read back by an
// independent USD reader, TinyUSDZ (npm package tinyusdz, a WebAssembly
// build), and compared with the run's own files read here independently:
//
//   node check_stage.mjs RUN_DIR [ROOT.usda] [--no-scene-parts]
//   (ROOT default RUN_DIR/run.usda)
//
// Every layer of the stage (root, per-frame layers, manifests) must load.
// TinyUSDZ parses value clips' metadata but does not compose them, so this
// script resolves the clips as USD defines it (the last `active` entry at
// or before the time, `times` mapping stage to clip time) and reads the
// values from the clip layer through the reader. Exit status 0: all checks
// passed; 77: skipped (no tinyusdz installed); 1: a check failed.
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath, pathToFileURL } from 'node:url';

const here = path.dirname(fileURLToPath(import.meta.url));
const packageDir = path.join(here, 'node_modules', 'tinyusdz');
if (!fs.existsSync(path.join(packageDir, 'tinyusdz.wasm'))) {
  console.log(`SKIP: the npm package tinyusdz is not installed in ${here} ` +
              '(scripts/install_deps.sh runs `npm ci` there where node and npm are present)');
  process.exit(77);
}

// --no-scene-parts: a pbf built without pbf_render (PBF_BUILD_VIEWER=OFF)
// writes no solids, body shapes or camera.
const sceneParts = !process.argv.includes('--no-scene-parts');
const [runDir, rootArg] = process.argv.slice(2).filter((a) => a !== '--no-scene-parts');
if (!runDir) {
  console.error('usage: node check_stage.mjs RUN_DIR [ROOT.usda]');
  process.exit(2);
}
const rootFile = rootArg ?? path.join(runDir, 'run.usda');
let failures = 0;
function check(ok, message) {
  if (!ok) {
    failures += 1;
    console.log(`FAIL: ${message}`);
  }
  return ok;
}

// tinyusdz.js is built for browsers: it refuses Node unless it looks like
// Electron's renderer, and it cannot fetch its .wasm, so it gets the bytes.
process.type = 'renderer';
globalThis.window = globalThis;
const init = (await import(pathToFileURL(path.join(packageDir, 'tinyusdz.js')))).default;
const tinyusdz = await init({ wasmBinary: fs.readFileSync(path.join(packageDir, 'tinyusdz.wasm')) });

// A layer as the reader understood it (its own .usda rendering of the
// layer); with `keep` false only whether it loads (true) or not (null).
function readLayer(file, keep = true) {
  const loader = new tinyusdz.TinyUSDZLoaderNative();
  const ok = loader.loadAsLayerFromBinary(new Uint8Array(fs.readFileSync(file)), file);
  const text = ok ? (keep ? loader.layerToString() : true) : null;
  if (!ok) check(false, `${file}: tinyusdz cannot read it: ${loader.error()}`);
  loader.delete();
  return text;
}
function readLayerText(text, name) {
  const loader = new tinyusdz.TinyUSDZLoaderNative();
  const ok = loader.loadAsLayerFromBinary(new TextEncoder().encode(text), name);
  const out = ok ? loader.layerToString() : null;
  loader.delete();
  return out;
}

// TinyUSDZ 0.9.0-rc10 misreads int64 (and uint) values of .usda files below
// 10^10: 123456 comes back as 1 (its integer parser), while int (int32) is
// read right. The `ids` of UsdGeomPoints are int64 by the schema; where the
// reader has this bug they are compared from the layer's own text instead,
// and this script says so.
const int64Probe = readLayerText('#usda 1.0\ndef Points "p"\n{\n    int64[] ids = [123456]\n}\n', 'probe.usda');
const int64Works = int64Probe !== null && /ids = \[123456\]/.test(int64Probe);
if (!int64Works)
  console.log('note: this tinyusdz misreads int64 in .usda (123456 -> 1): ids are compared ' +
              'from the layers\' text, positions and everything else through the reader');

const numberPattern = /[-+]?(?:inf|nan|(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)/gi;
const numbers = (text) => (text.match(numberPattern) ?? []).map(Number);

// The text of prim `name` (`def <Type> "name"`) up to the next prim at the same indent.
function primText(layer, type, name) {
  const head = new RegExp(`^( *)def ${type} "${name}"`, 'm');
  const m = head.exec(layer);
  if (!m) return null;
  const rest = layer.slice(m.index + m[0].length);
  const next = new RegExp(`^${m[1]}def `, 'm').exec(rest);
  return next ? rest.slice(0, next.index) : rest;
}
// `type name = value` (one line) in a prim's or layer's text.
function valueOf(text, declaration) {
  const escaped = declaration.replace(/[.*+?^${}()|[\]\\]/g, '\\$&');
  const m = new RegExp(`^\\s*${escaped} = (.*)$`, 'm').exec(text);
  return m ? m[1] : null;
}
// The value of `declaration.timeSamples` at `time`.
function sampleOf(text, declaration, time) {
  const escaped = declaration.replace(/[.*+?^${}()|[\]\\]/g, '\\$&');
  const m = new RegExp(`^\\s*${escaped}\\.timeSamples = \\{\\n([\\s\\S]*?)^\\s*\\}`, 'm').exec(text);
  if (!m) return null;
  for (const line of m[1].split('\n')) {
    const s = /^\s*([-+0-9.eE]+): (.*),\s*$/.exec(line);
    if (s && Number(s[1]) === time) return s[2];
  }
  return null;
}
const metadataOf = (layer, key) => {
  const m = new RegExp(`^    ${key} = (.*)$`, 'm').exec(layer.split('\ndef ')[0]);
  return m ? m[1].replace(/^"(.*)"$/, '$1') : null;
};

// A binary little-endian PLY: each element's properties as columns.
function readPly(file) {
  const bytes = fs.readFileSync(file);
  const end = bytes.indexOf('end_header\n');
  const header = bytes.subarray(0, end).toString('latin1').split('\n');
  const elements = [];
  for (const line of header) {
    const w = line.trim().split(/\s+/);
    if (w[0] === 'element') elements.push({ name: w[1], count: Number(w[2]), props: [] });
    else if (w[0] === 'property' && w[1] === 'list') elements.at(-1).props.push({ list: true, name: w[4] });
    else if (w[0] === 'property') elements.at(-1).props.push({ type: w[1], name: w[2] });
  }
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  let at = end + 'end_header\n'.length;
  const out = {};
  for (const e of elements) {
    const columns = Object.fromEntries(e.props.map((p) => [p.name, []]));
    for (let i = 0; i < e.count; ++i) {
      for (const p of e.props) {
        if (p.list) {
          const n = view.getUint8(at); at += 1;
          const list = [];
          for (let k = 0; k < n; ++k, at += 4) list.push(view.getUint32(at, true));
          columns[p.name].push(list);
        } else if (p.type === 'float') { columns[p.name].push(view.getFloat32(at, true)); at += 4; }
        else if (p.type === 'uint') { columns[p.name].push(view.getUint32(at, true)); at += 4; }
        else if (p.type === 'uchar') { columns[p.name].push(view.getUint8(at)); at += 1; }
        else throw new Error(`${file}: property type ${p.type}`);
      }
    }
    out[e.name] = { count: e.count, ...columns };
  }
  return out;
}

// Equal as floats: the reader's decimal, rounded to float, is the file's float.
function sameFloats(values, expected, what) {
  if (!check(values.length === expected.length,
             `${what}: ${values.length} values, expected ${expected.length}`)) return;
  for (let i = 0; i < values.length; ++i)
    if (Math.fround(values[i]) !== expected[i] && !(Number.isNaN(values[i]) && Number.isNaN(expected[i]))) {
      check(false, `${what}[${i}] = ${values[i]}, expected ${expected[i]} (as a float)`);
      return;
    }
}
function interleave(...columns) {
  const out = [];
  for (let i = 0; i < columns[0].length; ++i) for (const c of columns) out.push(c[i]);
  return out;
}

// The run's own description.
const summary = JSON.parse(fs.readFileSync(path.join(runDir, 'summary.json'), 'utf8'));
const fps = summary.fps;
const lastFrame = summary.frames;
const rootDir = path.dirname(rootFile);

// ---- the root layer: time metadata, the prims, the clip metadata ----
const root = readLayer(rootFile);
if (root === null) process.exit(1);
check(metadataOf(root, 'upAxis') === 'Y', `upAxis ${metadataOf(root, 'upAxis')}, expected Y`);
check(Number(metadataOf(root, 'metersPerUnit')) === 1, 'metersPerUnit is not 1');
check(Number(metadataOf(root, 'timeCodesPerSecond')) === fps,
      `timeCodesPerSecond ${metadataOf(root, 'timeCodesPerSecond')}, expected the run's fps ${fps}`);
check(Number(metadataOf(root, 'framesPerSecond')) === fps, 'framesPerSecond is not the fps');
check(Number(metadataOf(root, 'startTimeCode')) === 0, 'startTimeCode is not 0');
check(Number(metadataOf(root, 'endTimeCode')) === lastFrame,
      `endTimeCode ${metadataOf(root, 'endTimeCode')}, expected the last frame ${lastFrame}`);
check(metadataOf(root, 'defaultPrim') === 'run', 'defaultPrim is not run');
check(/^def Xform "run"/m.test(root), 'no /run Xform');

// A clip series: its metadata through the reader, and every layer it names
// loaded (the text of those that the checks read is asked for again then).
const layers = new Map();
function clipSeries(type, name) {
  const prim = primText(root, type, name);
  if (!prim) return null;
  const paths = (valueOf(prim, 'asset[] assetPaths') ?? '').match(/@[^@]*@/g)?.map((s) => s.slice(1, -1)) ?? [];
  const pairs = (text) => {
    const n = numbers(text ?? '');
    return Array.from({ length: n.length / 2 }, (_, k) => [n[2 * k], n[2 * k + 1]]);
  };
  const series = {
    name, paths, active: pairs(valueOf(prim, 'double2[] active')),
    times: pairs(valueOf(prim, 'double2[] times')),
    primPath: valueOf(prim, 'string primPath')?.replace(/"/g, ''),
    manifest: valueOf(prim, 'asset manifestAssetPath')?.replace(/@/g, ''),
  };
  check(series.primPath === `/${name}`, `${name}: clip primPath ${series.primPath}`);
  check(series.paths.length > 0 && series.active.length === series.paths.length &&
        series.times.length === series.paths.length,
        `${name}: ${series.paths.length} clip layers, ${series.active.length} active entries, ` +
        `${series.times.length} times`);
  for (const p of [...series.paths, series.manifest]) {
    const file = path.join(rootDir, p ?? '');
    if (!check(p && fs.existsSync(file), `${name}: clip layer ${p} does not exist`)) continue;
    layers.set(p, readLayer(file, false));
  }
  return series;
}
// The clip layer and clip time that give `series` its value at stage time `t`.
function resolve(series, t, read = true) {
  let index = -1;
  for (const [time, clip] of series.active) if (time <= t) index = clip;
  if (index < 0) return null;
  const times = series.times;
  let clipTime = times[0][1] + (t - times[0][0]);
  for (let k = 0; k + 1 < times.length; ++k)
    if (times[k][0] <= t && t <= times[k + 1][0])
      clipTime = times[k][1] + (t - times[k][0]) * (times[k + 1][1] - times[k][1]) /
                 (times[k + 1][0] - times[k][0]);
  if (t >= times.at(-1)[0]) clipTime = times.at(-1)[1] + (t - times.at(-1)[0]);
  const file = series.paths[index];
  const layer = read && layers.get(file) ? readLayer(path.join(rootDir, file)) : null;
  return { layer, file, time: clipTime };
}

const frameFile = (prefix, frame) => `${prefix}_${String(frame).padStart(5, '0')}.ply`;
const checkTimes = [0, Math.floor(lastFrame / 2), lastFrame];

// ---- particles ----
const particles = clipSeries('Points', 'particles');
if (check(particles !== null, 'no /run/particles Points')) {
  check(particles.paths.length === lastFrame + 1,
        `particles: ${particles.paths.length} clip layers for frames 0 to ${lastFrame}`);
  // Between two frames the earlier frame holds.
  const between = resolve(particles, 1.5, false);
  check(between?.file === particles.paths[1] && between.time === 1.5,
        'particles: at time 1.5 the clip of frame 1 is not the active one');
  for (const t of checkTimes) {
    const ply = readPly(path.join(runDir, frameFile('frame', t))).vertex;
    const r = resolve(particles, t);
    if (!check(r && r.layer, `particles: no clip layer at time ${t}`)) continue;
    const what = `particles at time code ${t} (${r.file})`;
    const before = failures;
    const prim = primText(r.layer, 'Points', 'particles');
    if (!check(prim !== null, `${what}: no Points "particles"`)) continue;
    const points = numbers(sampleOf(prim, 'point3f[] points', r.time) ?? '');
    check(points.length === 3 * ply.count, `${what}: ${points.length / 3} points, the PLY frame has ${ply.count}`);
    sameFloats(points, interleave(ply.x, ply.y, ply.z), `${what}: points`);
    sameFloats(numbers(sampleOf(prim, 'vector3f[] velocities', r.time) ?? ''),
               interleave(ply.vx, ply.vy, ply.vz), `${what}: velocities`);
    sameFloats(numbers(sampleOf(prim, 'float[] primvars:density', r.time) ?? ''), ply.density,
               `${what}: primvars:density`);
    const widths = numbers(sampleOf(prim, 'float[] widths', r.time) ?? '');
    check(widths.length === ply.count &&
          widths.every((w) => Math.fround(w) === Math.fround(2 * summary.particle_radius)),
          `${what}: widths are not ${ply.count} times the particle diameter`);
    let ids;
    if (int64Works) {
      ids = numbers(sampleOf(prim, 'int64[] ids', r.time) ?? '');
    } else {
      const own = primText(fs.readFileSync(path.join(rootDir, r.file), 'utf8'), 'Points', 'particles');
      ids = numbers(sampleOf(own, 'int64[] ids', r.time) ?? '');
      check(numbers(sampleOf(prim, 'int64[] ids', r.time) ?? '').length === ply.count,
            `${what}: the reader's ids do not have one value per particle`);
    }
    check(ids.length === ply.count && ids.every((id, i) => id === ply.id[i]),
          `${what}: ids differ from the PLY frame's`);
    const extent = numbers(sampleOf(prim, 'float3[] extent', r.time) ?? '');
    check(extent.length === 6 && ply.x.every((x, i) =>
            x >= extent[0] && x <= extent[3] && ply.y[i] >= extent[1] && ply.y[i] <= extent[4] &&
            ply.z[i] >= extent[2] && ply.z[i] <= extent[5]),
          `${what}: extent ${extent} does not hold every point`);
    if (failures === before)
      console.log(`particles at time code ${t}: ${ply.count} points, ids, velocities, density equal the PLY frame`);
  }
  const declared = primText(root, 'Points', 'particles');
  check(/primvars:density \(\s*interpolation = "vertex"/.test(declared),
        'particles: primvars:density is not declared with vertex interpolation');
}

// ---- surface meshes (where `pbf mesh` made them) ----
const surfaceFrames = fs.existsSync(path.join(runDir, 'surface'))
  ? fs.readdirSync(path.join(runDir, 'surface')).filter((f) => /^surface_\d{5,}\.ply$/.test(f)) : [];
const surface = clipSeries('Mesh', 'surface');
if (surfaceFrames.length > 0 && check(surface !== null, 'no /run/surface Mesh though the run has surfaces')) {
  check(surface.paths.length === surfaceFrames.length,
        `surface: ${surface.paths.length} clip layers for ${surfaceFrames.length} surface files`);
  for (const t of checkTimes) {
    const file = path.join(runDir, 'surface', frameFile('surface', t));
    if (!fs.existsSync(file)) continue;
    const ply = readPly(file);
    const r = resolve(surface, t);
    const what = `surface at time code ${t} (${r?.file})`;
    const before = failures;
    const prim = r?.layer ? primText(r.layer, 'Mesh', 'surface') : null;
    if (!check(prim !== null, `${what}: no Mesh "surface"`)) continue;
    const counts = numbers(sampleOf(prim, 'int[] faceVertexCounts', r.time) ?? '');
    check(counts.length === ply.face.count && counts.every((c) => c === 3),
          `${what}: ${counts.length} faces, pbf mesh's PLY has ${ply.face.count} triangles`);
    const indices = numbers(sampleOf(prim, 'int[] faceVertexIndices', r.time) ?? '');
    check(indices.length === 3 * ply.face.count &&
          ply.face.vertex_indices.flat().every((v, i) => v === indices[i]),
          `${what}: faceVertexIndices differ from the PLY's faces`);
    sameFloats(numbers(sampleOf(prim, 'point3f[] points', r.time) ?? ''),
               interleave(ply.vertex.x, ply.vertex.y, ply.vertex.z), `${what}: points`);
    sameFloats(numbers(sampleOf(prim, 'normal3f[] normals', r.time) ?? ''),
               interleave(ply.vertex.nx, ply.vertex.ny, ply.vertex.nz), `${what}: normals`);
    if (failures === before)
      console.log(`surface at time code ${t}: ${ply.face.count} faces, ${ply.vertex.count} vertices equal pbf mesh's PLY`);
  }
}

// ---- white water (where `pbf foam` made it) ----
const foamFrames = fs.readdirSync(runDir).filter((f) => /^diffuse_\d{5,}\.ply$/.test(f));
const foam = clipSeries('Points', 'whitewater');
if (foamFrames.length > 0 && check(foam !== null, 'no /run/whitewater Points though the run has white water')) {
  const t = lastFrame;
  const ply = readPly(path.join(runDir, frameFile('diffuse', t))).vertex;
  const r = resolve(foam, t);
  const prim = r?.layer ? primText(r.layer, 'Points', 'whitewater') : null;
  const before = failures;
  if (check(prim !== null, `whitewater at ${t}: no Points`)) {
    sameFloats(numbers(sampleOf(prim, 'point3f[] points', r.time) ?? ''),
               interleave(ply.x, ply.y, ply.z), `whitewater at time code ${t}: points`);
    const kinds = numbers(sampleOf(prim, 'int[] primvars:type', r.time) ?? '');
    check(kinds.length === ply.count && kinds.every((k, i) => k === ply.type[i]),
          `whitewater at time code ${t}: primvars:type differs from the PLY's type`);
    if (failures === before)
      console.log(`whitewater at time code ${t}: ${ply.count} points and types equal pbf foam's PLY`);
  }
}

// ---- rigid bodies: transforms from bodies.csv ----
const bodiesFile = path.join(runDir, 'bodies.csv');
if (fs.existsSync(bodiesFile)) {
  const [header, ...rows] = fs.readFileSync(bodiesFile, 'utf8').trim().split('\n');
  const names = header.split(',');
  const column = (row, name) => Number(row.split(',')[names.indexOf(name)]);
  const t = Math.floor(lastFrame / 2) + 1;
  const atT = rows.filter((row) => column(row, 'frame') === t);
  check(atT.length > 0, `bodies.csv has no row of frame ${t}`);
  for (const row of atT) {
    const body = column(row, 'body');
    const prim = primText(root, 'Xform', `body_${body}`);
    const before = failures;
    if (!check(prim !== null, `no /run/bodies/body_${body} Xform`)) continue;
    const translate = numbers(sampleOf(prim, 'double3 xformOp:translate', t) ?? '');
    const orient = numbers(sampleOf(prim, 'quatd xformOp:orient', t) ?? '');
    const expected = ['x', 'y', 'z', 'qw', 'qx', 'qy', 'qz'].map((n) => column(row, n));
    check(translate.length === 3 && orient.length === 4 &&
          [...translate, ...orient].every((v, i) => v === expected[i]),
          `body_${body} at time code ${t}: translate ${translate} orient ${orient}, bodies.csv says ${expected}`);
    check(/xformOpOrder = \["xformOp:translate", "xformOp:orient"\]/.test(prim),
          `body_${body}: xformOpOrder is not translate, orient`);
    if (sceneParts) check(/def Mesh "shape"/.test(prim), `body_${body}: no shape mesh`);
    if (failures === before)
      console.log(`body_${body} at time code ${t}: translate and orient equal bodies.csv`);
  }
}

// ---- solids and camera from the scene ----
if (sceneParts && summary.scene_file && fs.existsSync(summary.scene_file)) {
  const scene = JSON.parse(fs.readFileSync(summary.scene_file, 'utf8'));
  // The run's --set overrides of `solids` (summary.json records them) win.
  const solidsOverride = (summary.scene_overrides ?? []).findLast((o) => o.startsWith('solids='));
  const solids = (solidsOverride ? JSON.parse(solidsOverride.slice('solids='.length))
                                 : scene.solids ?? []).length;
  for (let k = 0; k < solids; ++k) {
    const prim = primText(root, 'Mesh', `solid_${k}`);
    check(prim !== null && numbers(valueOf(prim, 'int[] faceVertexCounts') ?? '').length > 0,
          `no /run/solids/solid_${k} Mesh with faces`);
  }
  const camera = primText(root, 'Camera', 'camera');
  check(camera !== null && numbers(valueOf(camera, 'matrix4d xformOp:transform') ?? '').length === 16,
        'no /run/camera with a transform');
  console.log(`${solids} solids and the camera are in the stage`);
}

console.log(`${layers.size + 1} layers read by tinyusdz`);
if (failures > 0) {
  console.log(`usd: ${failures} checks failed`);
  process.exit(1);
}
console.log('usd: all checks passed');
