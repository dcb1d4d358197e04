// Generates an ez-tree preset and writes it as OBJ, byte-identical across runs.
//
// Usage: node gen_tree.mjs <prefix> <preset name> <out.obj>
//   <prefix>/node_modules/ holds @dgreenheck/ez-tree (1.1.0) and three (0.187.0), each
//   unpacked from `npm pack` (no npm install: nothing else is needed). The folder must be
//   called node_modules: that is where Node resolves ez-tree's bare `import "three"`.
//
// Why the stubs: ez-tree's module loads its bark/leaf textures at import time through
// three's TextureLoader, which creates <img> elements; Node has no DOM. The textures are
// irrelevant to geometry, so a document whose images never load is enough.
import { pathToFileURL } from 'node:url';
import { join, resolve } from 'node:path';
import { writeFileSync, renameSync } from 'node:fs';

const [prefix, presetName, outPath] = process.argv.slice(2);
if (!prefix || !presetName || !outPath) {
  console.error('usage: node gen_tree.mjs <prefix> <preset name> <out.obj>');
  process.exit(2);
}

// V8's Math functions may round differently in other major versions, which changes bytes.
if (!process.versions.node.startsWith('20.')) {
  console.error(`warning: node ${process.version}; the pinned OBJ digest was made with Node 20`);
}

function fakeElement() {
  return {
    style: {},
    addEventListener() {},
    removeEventListener() {},
    setAttribute() {},
    getContext() { return null; },
  };
}
globalThis.document = {
  createElementNS: () => fakeElement(),
  createElement: () => fakeElement(),
};

const dir = join(resolve(prefix), 'node_modules');
const load = (p) => import(pathToFileURL(join(dir, p)).href);
// Both resolve bare 'three' to <dir>/three, so ez-tree and the exporter share one THREE.
const { Tree, TreePreset } = await load('@dgreenheck/ez-tree/build/ez-tree.es.js');
const { OBJExporter } = await load('three/examples/jsm/exporters/OBJExporter.js');

// An unknown name would silently give ez-tree's default tree.
if (!(presetName in TreePreset)) {
  console.error(`unknown preset "${presetName}"; known: ${Object.keys(TreePreset).join(', ')}`);
  process.exit(1);
}
const tree = new Tree();
tree.loadPreset(presetName);
tree.updateMatrixWorld(true);
const obj = new OBJExporter().parse(tree);

// Write to a temp name and rename, so a crash never leaves a partial OBJ behind.
const tmp = `${outPath}.tmp-${process.pid}`;
writeFileSync(tmp, obj);
renameSync(tmp, outPath);

const count = (geometry) =>
  (geometry.index ? geometry.index.count : geometry.attributes.position.count) / 3;
console.log(JSON.stringify({
  preset: presetName,
  vertices: tree.branchesMesh.geometry.attributes.position.count
    + tree.leavesMesh.geometry.attributes.position.count,
  triangles: count(tree.branchesMesh.geometry) + count(tree.leavesMesh.geometry),
  bytes: Buffer.byteLength(obj),
}));
