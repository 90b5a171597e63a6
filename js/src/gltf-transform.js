// tessella/gltf-transform: a glTF-Transform (https://gltf-transform.dev) transform that refines
// every triangle primitive of a Document with tessella's refineGltf, in place.
import { GLB_BUFFER, Logger, PropertyType, WebIO } from '@gltf-transform/core';
import { ready, refineGltfWithReport, TessellaError } from './index.js';

// Geometry compression the Document's own I/O applies on writing. The geometry in a Document is
// always decoded, so the copy tessella refines is written without it; the extensions stay on
// the Document (a later write compresses the refined geometry).
const COMPRESSION = new Set(['KHR_draco_mesh_compression', 'EXT_meshopt_compression', 'KHR_meshopt_compression']);

const TRIANGLE_MODES = new Set([4, 5, 6]); // TRIANGLES, TRIANGLE_STRIP, TRIANGLE_FAN

/**
 * A glTF-Transform transform: `await document.transform(tessellate({ scheme: 'pn', level: 3 }))`.
 *
 * Refines every triangle primitive of the Document (options as `refineGltf`'s: `scheme`,
 * `level` or `maxEdge`, `alpha`, `normals`), in place: each primitive keeps its identity, its
 * material and extensions, and gets the refined attributes, indices and morph targets
 * (`NORMAL` added where it had none, `TANGENT` recomputed, strips and fans become triangle
 * lists). Nodes, materials, textures, skins, animations and every extension of the Document are
 * untouched. Points and lines stay as they are.
 *
 * How: the Document is written as glTF (with a `WebIO` of its own that registers the
 * Document's extensions, minus geometry compression: the Document holds decoded geometry),
 * refined by `refineGltf`, the result read into a second Document, and its primitives' data
 * copied over; accessors no longer used are disposed. `await ready` is done for you.
 */
export function tessellate(options = {}) {
  if (options == null || typeof options !== 'object') throw new TessellaError('tessellate takes an options object');
  if ('buffers' in options) throw new TessellaError('tessellate: buffers is not an option here (the Document holds its buffers)');
  const refineOptions = { ...options };
  return async function tessellate(document) {
    await ready;
    const root = document.getRoot();
    const logger = document.getLogger();
    const extensions = root
      .listExtensionsUsed()
      .filter((e) => !COMPRESSION.has(e.extensionName))
      .map((e) => e.constructor);
    // Errors only: leaving out the compression extensions is on purpose.
    const io = new WebIO().setLogger(new Logger(Logger.Verbosity.ERROR)).registerExtensions(extensions);

    const { json, resources } = await io.writeJSON(document, { format: 'GLTF', basename: 'tessella' });
    const buffers = {};
    for (const b of json.buffers ?? []) if (b.uri !== undefined) buffers[b.uri] = resources[b.uri];
    const { glb, primitives: report } = refineGltfWithReport(new TextEncoder().encode(JSON.stringify(json)), {
      ...refineOptions,
      buffers,
    });

    // The refined GLB, with the images (named by URI, as written) from the first write.
    const refinedJson = glbJson(glb);
    const refined = await io.readJSON({ json: refinedJson.json, resources: { ...resources, [GLB_BUFFER]: refinedJson.bin } });

    const meshes = root.listMeshes();
    const refinedMeshes = refined.getRoot().listMeshes();
    if (meshes.length !== refinedMeshes.length) {
      throw new TessellaError(`tessellate: the refined file has ${refinedMeshes.length} meshes, the Document ${meshes.length}`);
    }
    const buffer = root.listBuffers()[0] ?? document.createBuffer();
    const replaced = new Set();
    let triangles = 0;
    for (const { mesh: m, primitive: p } of report) {
      const target = meshes[m].listPrimitives()[p];
      const source = refinedMeshes[m].listPrimitives()[p];
      if (target === undefined || source === undefined || !TRIANGLE_MODES.has(target.getMode())) {
        throw new TessellaError(`tessellate: mesh ${m} primitive ${p} of the refined file has no triangle primitive to replace in the Document`);
      }
      copyPrimitive(document, buffer, source, target, replaced);
      triangles += source.getIndices().getCount() / 3;
    }
    // Accessors only the replaced primitives used.
    for (const accessor of replaced) {
      if (accessor.listParents().every((p) => p.propertyType === PropertyType.ROOT)) accessor.dispose();
    }
    logger.debug(`tessellate: ${report.length} primitives refined, ${triangles} triangles.`);
  };
}

// Sets `target`'s mode, indices, attributes and morph targets' attributes to copies of
// `source`'s (another Document's); the accessors it let go of are added to `replaced`.
function copyPrimitive(document, buffer, source, target, replaced) {
  const copy = (a) =>
    a === null
      ? null
      : document
          .createAccessor(a.getName())
          .setType(a.getType())
          .setArray(a.getArray().slice())
          .setNormalized(a.getNormalized())
          .setSparse(a.getSparse())
          .setBuffer(buffer);
  const setAll = (from, to) => {
    for (const semantic of to.listSemantics()) {
      replaced.add(to.getAttribute(semantic));
      to.setAttribute(semantic, null);
    }
    for (const semantic of from.listSemantics()) to.setAttribute(semantic, copy(from.getAttribute(semantic)));
  };
  const targets = target.listTargets();
  const sourceTargets = source.listTargets();
  if (targets.length !== sourceTargets.length) {
    throw new TessellaError(`tessellate: a primitive has ${targets.length} morph targets, its refined one ${sourceTargets.length}`);
  }
  if (target.getIndices() !== null) replaced.add(target.getIndices());
  target.setIndices(copy(source.getIndices()));
  target.setMode(source.getMode());
  setAll(source, target);
  targets.forEach((t, i) => setAll(sourceTargets[i], t));
}

// The JSON and the BIN chunk of a GLB (what refineGltf writes: one JSON chunk, then the BIN).
function glbJson(glb) {
  const view = new DataView(glb.buffer, glb.byteOffset, glb.byteLength);
  const jsonLength = view.getUint32(12, true);
  const json = JSON.parse(new TextDecoder().decode(glb.subarray(20, 20 + jsonLength)));
  const binAt = 20 + jsonLength;
  const bin = binAt + 8 <= glb.byteLength ? glb.subarray(binAt + 8, binAt + 8 + view.getUint32(binAt, true)) : new Uint8Array(0);
  return { json, bin };
}
