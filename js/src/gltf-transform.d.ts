import type { Transform } from '@gltf-transform/core';
import type { RefineGltfOptions } from './index.js';

/** `refineGltf`'s options: `scheme`, `level` or `maxEdge`, `alpha`, `normals` (the Document holds its buffers). */
export type TessellateOptions = Omit<RefineGltfOptions, 'buffers'>;

/**
 * A glTF-Transform transform refining every triangle primitive of a Document in place:
 * `await document.transform(tessellate({ scheme: 'pn', level: 3 }))`. Primitives keep their
 * identity, material and extensions; nodes, materials, textures, skins, animations are untouched.
 */
export function tessellate(options?: TessellateOptions): Transform;
