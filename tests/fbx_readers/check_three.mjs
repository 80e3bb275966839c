// What three.js's FBXLoader (npm `three`, pinned in package.json) reads of an FBX file, as JSON
// on stdout, for compare.py: every console.warn/console.error it printed, the object tree, each
// clip's name, duration and tracks, the file's UnitScaleFactor (FBXLoader keeps lengths in the
// file's units and says the factor in userData), and every object's world position at the
// frames given, played by an AnimationMixer at time frame / (frames − 1) × the clip's duration.
//
//   node check_three.mjs FILE.fbx FRAMES F1 F2 …      (FRAMES: the take's frame count)
//
// Runs in node without a DOM: FBXLoader.parse reads binary FBX from an ArrayBuffer, and a file
// without textures never asks for an image.
import { readFileSync } from 'node:fs';
import { AnimationMixer, LoopOnce, REVISION, Vector3 } from 'three';
import { FBXLoader } from 'three/examples/jsm/loaders/FBXLoader.js';

const [file, framesArg, ...frameArgs] = process.argv.slice(2);
if (!file || framesArg === undefined) {
  console.error('usage: node check_three.mjs FILE.fbx FRAMES [FRAME …]');
  process.exit(2);
}
const frames = Number(framesArg);

const messages = [];
const keep = (level) => (...args) => {
  messages.push(`${level}: ${args.map((a) => (typeof a === 'string' ? a : String(a))).join(' ')}`);
};
console.warn = keep('warn');
console.error = keep('error');
console.log = keep('log');
console.info = keep('info');

const out = { reader: `three.js r${REVISION} FBXLoader`, messages };
let root;
try {
  const bytes = readFileSync(file);
  const buffer = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength);
  root = new FBXLoader().parse(buffer, '');
} catch (error) {
  out.error = String(error && error.stack ? error.stack : error);
  process.stdout.write(JSON.stringify(out) + '\n');
  process.exit(1);
}

out.unit_scale_factor = root.userData.unitScaleFactor ?? null;
const objects = [];
const index = new Map();
root.traverse((object) => {
  index.set(object, objects.length);
  objects.push(object);
});
out.nodes = objects.map((o) => [o.name, o.parent && index.has(o.parent) ? index.get(o.parent) : -1]);
out.animations = root.animations.map((clip) => ({
  name: clip.name,
  duration: clip.duration,
  ticks_per_second: 1,
  channels: clip.tracks.map((track) => ({ node: track.name, keys: track.times.length })),
}));

out.frames = [];
const clip = root.animations[0];
const mixer = new AnimationMixer(root);
if (clip) {
  // Played once and held at its end: a repeating clip is back at its start at t = duration.
  const action = mixer.clipAction(clip);
  action.setLoop(LoopOnce, 1);
  action.clampWhenFinished = true;
  action.play();
}
const duration = clip ? clip.duration : 0;
for (const arg of frameArgs) {
  const frame = Number(arg);
  const time = frames > 1 ? (duration * frame) / (frames - 1) : 0;
  mixer.setTime(time);
  root.updateMatrixWorld(true);
  const positions = objects.map((o) => o.getWorldPosition(new Vector3()).toArray());
  out.frames.push({ frame, time, positions });
}
process.stdout.write(JSON.stringify(out) + '\n');
