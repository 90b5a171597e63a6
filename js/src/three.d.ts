import type { BufferGeometry } from 'three';
import type { RefineOptions } from './index.js';

/**
 * Refines a BufferGeometry into a new indexed one: position, normal, uv from tessella; other
 * float attributes interpolated over each coarse triangle.
 */
export function refineGeometry(geometry: BufferGeometry, options?: Omit<RefineOptions, 'origin'>): BufferGeometry;

export interface RefinedGeometryOptions extends Omit<RefineOptions, 'origin'> {
  /** Use the source's normal attribute each frame (default: when it has one); false recomputes them. */
  normalsFromSource?: boolean;
}

/** A refined geometry that follows a deforming source; `update()` rewrites its attributes in place. */
export class RefinedGeometry {
  constructor(source: BufferGeometry, options?: RefinedGeometryOptions);
  /** The refined geometry; its attribute arrays are reused by every `update()`. */
  readonly geometry: BufferGeometry;
  /** Refines the source's current positions (and normals) into `geometry`. */
  update(): BufferGeometry;
  /** Frees the wasm memory. */
  dispose(): void;
}
