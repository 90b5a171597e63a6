// TessellatedMesh's `lod` option (js/src/three.js): screen-space (or tolerance, or distance)
// levels per unique coarse edge, drawn with the GPU tessellator's patterns (crack-free: both
// faces of an edge place its points from the same level with the same 16.16 arithmetic and
// evaluate them from the edge's own control points). The spacing's parts (strips and
// interiors) are uploaded once; per frame the wasm (AdaptiveSurface) turns the camera into one
// packed record per face (an RGBA32UI texture) and one instance per face and part (a shared
// instanced buffer), and each part used is drawn by a child Mesh in one instanced draw.
import {
  BufferAttribute,
  DataTexture,
  FloatType,
  InstancedBufferGeometry,
  InstancedInterleavedBuffer,
  InterleavedBufferAttribute,
  Matrix4,
  Mesh,
  NearestFilter,
  RGBAFormat,
  RedIntegerFormat,
  RGBAIntegerFormat,
  UnsignedIntType,
  Vector2,
  Vector3,
  Vector4,
} from 'three';
import { maxTextureWidth, TessellaError } from './index.js';

/** Options a TessellatedMesh with `lod` reads itself (the camera and image size of the levels). */
export const LOD_MESH_OPTIONS = ['camera', 'size'];

// The vertex shader's additions for a part instance: the wasm's GLSL (placement and
// evaluation), the code and instance attributes, the corners texture for uvs and colours.
function lodVertexPatch(glsl, flags) {
  let head = `${glsl}in uint tessellaCode;\nin uint tessellaInstance;\n`;
  const body = [
    'vec3 tessellaPosition;',
    'vec3 tessellaNormal;',
    'vec3 tessellaL;',
    'tessella_adaptive_evaluate(tessellaCode, tessellaInstance, tessellaPosition, tessellaNormal, tessellaL);',
    'vec3 position = tessellaPosition;',
    'vec3 normal = tessellaNormal;',
  ];
  if (flags.uv || flags.color > 0) {
    head += 'uniform highp sampler2D tessellaCorners;\nuniform int tessellaCornersPerRow;\nuniform int tessellaCornerTexels;\n';
    head += 'vec4 tessella_corner(int face, int j) {\n    int row = face / tessellaCornersPerRow;\n    return texelFetch(tessellaCorners, ivec2((face - row * tessellaCornersPerRow) * tessellaCornerTexels + j, row), 0);\n}\n';
    body.push('int tessellaFace = int(tessellaInstance & 0x3fffffffu);');
  }
  const l = 'tessellaL';
  if (flags.uv) {
    body.push(
      'vec4 tessellaUv01 = tessella_corner(tessellaFace, 0);',
      'vec2 tessellaUv2 = tessella_corner(tessellaFace, 1).xy;',
      `vec2 uv = ${l}.x * tessellaUv01.xy + ${l}.y * tessellaUv01.zw + ${l}.z * tessellaUv2;`,
    );
  }
  if (flags.color > 0) {
    const at = flags.uv ? 2 : 0;
    body.push(
      `vec4 tessellaColor = ${l}.x * tessella_corner(tessellaFace, ${at}) + ${l}.y * tessella_corner(tessellaFace, ${at + 1}) + ${l}.z * tessella_corner(tessellaFace, ${at + 2});`,
      '#if defined( USE_COLOR_ALPHA )',
      'vec4 color = tessellaColor;',
      '#elif defined( USE_COLOR )',
      'vec3 color = tessellaColor.rgb;',
      '#endif',
    );
  }
  return { head, body: body.join('\n') + '\n' };
}

function checkSize(size) {
  if (size === undefined) return;
  if (!(Array.isArray(size) && size.length === 2 && size.every((x) => Number.isInteger(x) && x > 0))) {
    throw new TessellaError('size: the image size the levels are for, [width, height] in pixels');
  }
}

/**
 * The LOD drawing of one TessellatedMesh: the parts geometry, the records texture, the instance
 * buffer and a child Mesh per part drawn. `owner` is the TessellatedMesh, `surface` its
 * AdaptiveSurface.
 */
export class LodParts {
  #owner;
  #surface;
  #codes;
  #index;
  #normal;
  #ranges;
  #records;
  #instances;
  #children = new Map();
  #corners = null;
  #color = null;
  #key = null;
  #stale = true;
  #seenCamera = null;
  #seenSize = null;
  #levelsCamera = null;
  #given = false;
  #m = new Matrix4();
  #v = new Vector3();
  #t = new Vector3();
  #viewport = new Vector4();
  #size = new Vector2();
  #instancesTexture = null;
  #instancesWidth = 1;
  #instancesHeight = 1;
  #positions = false;

  constructor(owner, surface, options, flags) {
    if (options.camera !== undefined && options.camera !== null && options.camera.isCamera !== true) {
      throw new TessellaError('camera: the three.js Camera the levels are for (or leave it out: the camera of the last render)');
    }
    checkSize(options.size);
    this.#owner = owner;
    this.#surface = surface;
    /** Counts the levels drawn so far (each new set adds one). */
    this.levelsVersion = 0;
    /** The camera the levels are for; null: the camera of the last render. */
    this.camera = options.camera ?? null;
    /** The image size [width, height] the levels are for; null: the viewport of the last render. */
    this.size = options.size ?? null;
    this.#codes = new BufferAttribute(surface.partCodes(), 1);
    const wide = surface.partIndices();
    const indices = this.#codes.count <= 0x10000 ? Uint16Array.from(wide) : wide;
    this.#index = new BufferAttribute(indices, 1);
    // three shades a lit material flat without a normal attribute; the shader's normal is a
    // local that hides it (the attribute is never bound), so this one only has to exist: the
    // codes' buffer, uploaded once.
    this.#normal = this.#codes;
    this.#ranges = surface.partRanges();
    // The owner draws nothing (its children do), but with the same attributes: three picks a
    // material's program by the geometry too (without a normal it would shade flat).
    const g = owner.geometry;
    g.setIndex(this.#index);
    g.setAttribute('tessellaCode', this.#codes);
    g.setAttribute('normal', this.#normal);
    // Four-component colours: three reads their width from a color attribute (USE_COLOR_ALPHA);
    // the shader's colour is a local from the corners texture, so a stand-in of one entry.
    this.#color = flags.color === 4 ? new BufferAttribute(new Float32Array(4), 4) : null;
    if (this.#color !== null) g.setAttribute('color', this.#color);
    g.setDrawRange(0, 0);
    const records = new DataTexture(
      new Uint32Array(surface.recordsWidth * surface.recordsHeight * 4),
      surface.recordsWidth,
      surface.recordsHeight,
      RGBAIntegerFormat,
      UnsignedIntType,
    );
    // No internalFormat: WebGLRenderer derives RGBA32UI, WebGPURenderer rgba32uint (it would
    // take a WebGL name as the GPU format and fail to create the texture).
    records.minFilter = NearestFilter;
    records.magFilter = NearestFilter;
    records.generateMipmaps = false;
    this.#records = records;
    // The instance words: the instanced buffer (WebGL) and, over the same array, an R32UI
    // texture (WebGPU, instancesTexture) whose rows hold the wasm's widest texture of words.
    const maxWidth = maxTextureWidth();
    const words = Math.max(4 * surface.faceCount, 1);
    this.#instancesWidth = Math.min(words, maxWidth);
    this.#instancesHeight = Math.ceil(words / this.#instancesWidth);
    this.#instances = new InstancedInterleavedBuffer(new Uint32Array(this.#instancesWidth * this.#instancesHeight), 1, 1);
    /** Bytes the last level change marked for upload (records and instances; 0 when the levels did not change). */
    this.uploadedBytes = 0;
    /** Parts (strips, interiors) built once: their vertices and indices. */
    this.partBytes = this.#codes.array.byteLength + indices.byteLength;
    this.uniforms = {
      tessellaRecords: { value: records },
      tessellaRecordsPerRow: { value: surface.recordsPerRow },
    };
    if (flags.uv || flags.color > 0) {
      const texels = (flags.uv ? 2 : 0) + (flags.color > 0 ? 3 : 0);
      const perRow = Math.min(Math.floor(maxWidth / texels), surface.faceCount);
      const height = Math.ceil(surface.faceCount / perRow);
      const tex = new DataTexture(new Float32Array(perRow * texels * height * 4), perRow * texels, height, RGBAFormat, FloatType);
      tex.minFilter = NearestFilter;
      tex.magFilter = NearestFilter;
      tex.generateMipmaps = false;
      this.#corners = { texture: tex, texels, perRow };
      this.uniforms.tessellaCorners = { value: tex };
      this.uniforms.tessellaCornersPerRow = { value: perRow };
      this.uniforms.tessellaCornerTexels = { value: texels };
    }
    this.flags = flags;
    /** Set by the owner: copies its own uniform values into its material's before a child draws. */
    this.bind = null;
  }

  /** The vertex shader patch (head, body) for the material. */
  patch(glsl) {
    return lodVertexPatch(glsl, this.flags);
  }

  /** The nets changed: the levels are computed again before the next render. */
  netsChanged() {
    this.#stale = true;
  }

  /** Copies the coarse uvs / colours (per face, three corners) into the corners texture; returns the bytes. */
  corners(uv, color, indices) {
    const c = this.#corners;
    if (c === null) return 0;
    const data = c.texture.image.data;
    const faces = indices.length / 3;
    for (let f = 0; f < faces; f++) {
      const row = Math.floor(f / c.perRow);
      let at = (row * c.perRow * c.texels + (f - row * c.perRow) * c.texels) * 4;
      const i = [indices[3 * f], indices[3 * f + 1], indices[3 * f + 2]];
      if (uv !== null) {
        data.set([uv[2 * i[0]], uv[2 * i[0] + 1], uv[2 * i[1]], uv[2 * i[1] + 1], uv[2 * i[2]], uv[2 * i[2] + 1], 0, 0], at);
        at += 8;
      }
      if (color !== null) {
        const n = color.itemSize;
        for (let k = 0; k < 3; k++) {
          for (let j = 0; j < 4; j++) data[at + 4 * k + j] = j < n ? color.data[i[k] * n + j] : 1;
        }
      }
    }
    c.texture.needsUpdate = true;
    return data.byteLength;
  }

  /** What a render tells: the camera and the viewport (physical pixels) it draws with. */
  seen(renderer, camera) {
    this.#forNodes(renderer);
    let size;
    if (renderer.isWebGPURenderer === true) {
      // Its render target's size, or the canvas's drawing buffer (it has no getCurrentViewport).
      const target = renderer.getRenderTarget();
      size = target !== null ? [target.width, target.height] : renderer.getDrawingBufferSize(this.#size).toArray();
    } else {
      renderer.getCurrentViewport(this.#viewport);
      size = [this.#viewport.z, this.#viewport.w];
    }
    const changed = this.#seenCamera !== camera || this.#seenSize === null || this.#seenSize[0] !== size[0] || this.#seenSize[1] !== size[1];
    this.#seenCamera = camera;
    this.#seenSize = size;
    if (changed && this.camera === null) this.#stale = true;
  }

  // Before any render has shown the camera (and without the camera and size options): the
  // mesh seen whole from three radii away down -z, 45° and 256×256 pixels (a modest first frame), so the first
  // render draws a surface; the next takes the real camera's levels.
  #firstView() {
    const sphere = this.#owner.geometry.boundingSphere;
    const [x, y, z] = sphere.center.toArray();
    const r = sphere.radius > 0 ? sphere.radius : 1;
    return { eye: [x, y, z + 3 * r], target: [x, y, z], fov: 45, size: [256, 256], camera: null, first: true };
  }

  /** The camera and size the levels are for, in the mesh's coordinates. */
  #view() {
    // A tolerance reads the nets alone.
    if (this.#surface.lod.startsWith('tolerance')) return { eye: [0, 0, 1], target: [0, 0, 0], fov: 45, size: [1, 1], camera: null };
    const camera = this.camera ?? this.#seenCamera;
    const size = this.size ?? this.#seenSize;
    if (camera === null || size === null) return this.#firstView();
    // Where the camera is now (three updates a parentless camera after the scene).
    if (camera.matrixWorldAutoUpdate === true) camera.updateWorldMatrix(true, false);
    const inverse = this.#m.copy(this.#owner.matrixWorld).invert();
    const eye = this.#v.setFromMatrixPosition(camera.matrixWorld);
    const ahead = this.#t.set(0, 0, -1).transformDirection(camera.matrixWorld).add(eye);
    eye.applyMatrix4(inverse);
    ahead.applyMatrix4(inverse);
    let fov = 45;
    if (camera.isPerspectiveCamera === true) {
      fov = (2 * Math.atan(Math.tan((camera.fov * Math.PI) / 360) / camera.zoom) * 180) / Math.PI;
    } else if (this.#surface.lod.startsWith('screen')) {
      throw new TessellaError(`lod '${this.#surface.lod}' measures edges on the screen of a PerspectiveCamera; this camera is not one`);
    }
    return { eye: eye.toArray(), target: ahead.toArray(), fov, size: [size[0], size[1]], camera };
  }

  /**
   * Before three culls and lists the scene (the owner's updateMatrixWorld): new levels when the
   * camera, the image size, the mesh's place or its nets changed, then the children drawn.
   */
  refresh() {
    if (this.#given) {
      this.uploadedBytes = 0;
      return;
    }
    const view = this.#view();
    const key = [...view.eye, ...view.target, view.fov, ...view.size].join(',');
    if (!this.#stale && key === this.#key) {
      this.uploadedBytes = 0;
      return;
    }
    this.#key = key;
    this.#stale = false;
    const s = this.#surface;
    s.setLod(view, view.size);
    this.#levelsCamera = view;
    this.levelsVersion++;
    const bytes = s.read(this.#records.image.data, this.#instances.array);
    this.#records.needsUpdate = true;
    this.#instances.clearUpdateRanges();
    this.#instances.addUpdateRange(0, Math.max(s.instanceCount, 1));
    this.#instances.needsUpdate = true;
    if (this.#instancesTexture !== null) this.#instancesTexture.needsUpdate = true;
    this.uploadedBytes = bytes;
    this.#place(s.draws);
  }

  /**
   * Levels given by the caller (one per unique edge, `surface.edgeCount`), drawn from the next
   * render on instead of the lod function's.
   */
  setLevels(levels) {
    const s = this.#surface;
    s.setLevels(levels);
    this.#levelsCamera = null;
    this.levelsVersion++;
    this.#given = true;
    this.uploadedBytes = s.read(this.#records.image.data, this.#instances.array);
    this.#records.needsUpdate = true;
    this.#instances.clearUpdateRanges();
    this.#instances.addUpdateRange(0, Math.max(s.instanceCount, 1));
    this.#instances.needsUpdate = true;
    if (this.#instancesTexture !== null) this.#instancesTexture.needsUpdate = true;
    this.#place(s.draws);
  }

  // WebGPURenderer (before an object's first draw: three calls onBeforeRender before it builds
  // the pipeline) reads a position attribute even where the positionNode replaces it, and warns
  // without one: the codes again, on the owner (whose pipeline three builds too) and the
  // children. Not under WebGLRenderer, whose shader's position is a local hiding the attribute,
  // and where Box3.setFromObject(object, true) would read the codes as points.
  #forNodes(renderer) {
    if (this.#positions || renderer?.isWebGPURenderer !== true) return;
    this.#positions = true;
    this.#owner.geometry.setAttribute('position', this.#codes);
    for (const child of this.#children.values()) child.geometry.setAttribute('position', this.#codes);
  }

  // One child per part drawn: its index range, its instances' offset in the shared buffer.
  #place(draws) {
    const owner = this.#owner;
    const used = new Set();
    for (let d = 0; d < draws.length; d += 3) {
      const [part, first, count] = [draws[d], draws[d + 1], draws[d + 2]];
      used.add(part);
      let child = this.#children.get(part);
      if (child === undefined) {
        const g = new InstancedBufferGeometry();
        g.setIndex(this.#index);
        g.setAttribute('tessellaCode', this.#codes);
        g.setAttribute('normal', this.#normal);
        if (this.#color !== null) g.setAttribute('color', this.#color);
        g.setDrawRange(this.#ranges[2 * part], this.#ranges[2 * part + 1]);
        g.boundingBox = owner.geometry.boundingBox;
        g.boundingSphere = owner.geometry.boundingSphere;
        child = new Mesh(g, owner.material);
        child.name = `tessella part ${part}`;
        child.raycast = () => {};
        // The owner's own values into the (possibly shared) material's uniforms before each draw.
        child.onBeforeRender = (renderer) => {
          this.#forNodes(renderer);
          this.bind?.(renderer);
        };
        if (this.#positions) g.setAttribute('position', this.#codes);
        child.customDepthMaterial = owner.customDepthMaterial;
        child.customDistanceMaterial = owner.customDistanceMaterial;
        this.#children.set(part, child);
        owner.add(child);
        child.updateMatrixWorld(true);
      }
      const g = child.geometry;
      const at = g.getAttribute('tessellaInstance');
      // A new attribute object when the offset moves: three rebinds the vertex array then.
      if (at === undefined || at.offset !== first) g.setAttribute('tessellaInstance', new InterleavedBufferAttribute(this.#instances, 1, first));
      g.instanceCount = count;
      // WebGPURenderer's nodes read the words at this first plus the instance index.
      child.userData.tessellaFirst = first;
      child.material = owner.material;
      child.castShadow = owner.castShadow;
      child.receiveShadow = owner.receiveShadow;
      child.visible = true;
    }
    for (const [part, child] of this.#children) if (!used.has(part)) child.visible = false;
  }

  /** The options `refine` makes the drawn levels with (the camera and size of the last levels). */
  refineOptions(base) {
    if (this.#given) throw new TessellaError('TessellatedMesh: raycasts hit the lod function\'s levels; levels given by setLevels have no CPU refinement to hit');
    const v = this.#levelsCamera;
    if (v === null) throw new TessellaError('TessellatedMesh: no levels yet to raycast (render it once, or give the camera and size options)');
    if (v.camera === null && v.first !== true) return { ...base };
    return { ...base, camera: [...v.eye, ...v.target, v.fov], size: v.size };
  }

  /** The records texture (RGBA32UI: per face its packed record). */
  get recordsTexture() {
    return this.#records;
  }

  /** The instance words (`face | side << 30`, each part's from its first) as an R32UI texture, maxTextureWidth() words a row (WebGPURenderer). */
  get instancesTexture() {
    if (this.#instancesTexture === null) {
      const t = new DataTexture(this.#instances.array, this.#instancesWidth, this.#instancesHeight, RedIntegerFormat, UnsignedIntType);
      t.minFilter = NearestFilter;
      t.magFilter = NearestFilter;
      t.generateMipmaps = false;
      t.needsUpdate = true;
      this.#instancesTexture = t;
    }
    return this.#instancesTexture;
  }

  /** The corners texture (RGBA32F: per face its corners' uvs, then colours), or null without uvs and colours. */
  get cornersTexture() {
    return this.#corners?.texture ?? null;
  }

  /** Triangles the last levels draw. */
  get triangleCount() {
    return this.#surface.triangleCount;
  }

  /** The children drawing the parts (one per part used so far; hidden when unused). */
  get children() {
    return [...this.#children.values()];
  }

  dispose() {
    for (const child of this.#children.values()) {
      child.geometry.dispose();
      this.#owner.remove(child);
    }
    this.#children.clear();
    this.#records.dispose();
    this.#instancesTexture?.dispose();
    this.#corners?.texture.dispose();
  }
}
