// bunraku/three: `PuppetMesh`, a three.js `Mesh` that draws a bunraku puppet, a `Player`'s
// document or a layered `Character`. three is an optional peer dependency, imported by its
// bare specifier (never bundled here).
//
// What it takes care of, so that a new user gets a picture and not a blank canvas:
// - winding: bunraku's triangles are counter-clockwise in y-up maths, i.e. clockwise on a
//   y-down screen, so a y-down camera would cull them all under three's `FrontSide`; the
//   material is `DoubleSide` (a picture is a flat sheet; folded triangles are drawn too, as
//   the `Renderer` draws them), so it shows under y-up and y-down, orthographic and
//   perspective cameras, and under a mirroring `scale`;
// - uvs are v-down (0 at the picture's top): the texture has `flipY = false`;
// - the texture is `SRGBColorSpace`, so its colours come out as the picture's;
// - bounds follow the pose: the bounding box and sphere are recomputed on every update, so
//   three's frustum culling stays on and correct;
// - no per-frame copy: the position attribute's array (xyz, z = 0) is the `Float32Array`
//   the solver (`puppet.updateInto`, `player.positionsInto`) writes into;
// - overlap depth (`triangleDepth`, keyed depths) by the order of the index buffer, and a
//   character's parts in their draw order (one group and material per part, with its
//   opacity and blend mode);
// - with `gather`, the rendered mesh gathered on the GPU from a simulation mesh: the material's
//   vertex shader computes each vertex from its parent simulation triangle, and a frame
//   uploads only the simulation positions (a small RG32F `DataTexture`; js/gl/gather.ts).

import * as THREE from "three";
import type { Character, Player, Puppet } from "./index.js";
import { depthOrder, hasDepth } from "./gl/depth.js";
import { GATHER_GLSL, gatherMesh } from "./gl/gather.js";

/** A picture: a three.js texture, anything WebGL uploads (an image, a canvas, an
 *  `ImageBitmap`, `ImageData`) or straight RGBA pixels `{ data, width, height }`, rows from
 *  the top. */
export type PuppetPicture =
  | THREE.Texture
  | HTMLImageElement
  | HTMLCanvasElement
  | OffscreenCanvas
  | ImageBitmap
  | ImageData
  | { readonly data: Uint8Array | Uint8ClampedArray; readonly width: number; readonly height: number };

/** A part of a layered character (a `Character`'s `parts`, or a document's `parts`). */
export interface PuppetMeshPart {
  readonly name: string;
  /** `[first, count]` of its triangles in the mesh (a document), or only `count` (a `Character`). */
  readonly triangles: readonly [number, number];
  readonly opacity?: number;
  readonly blendMode?: "normal" | "multiply" | "screen" | "additive";
  readonly visible?: boolean;
}

/** What a `PuppetMesh` draws. */
export type PuppetMeshSource =
  /** A compiled (or to be compiled) puppet and its picture; `uvs` one `[u, v]` per vertex,
   *  v down (`mesh.uvs`). The puppet's own triangles are drawn. */
  | { readonly puppet: Puppet; readonly uvs: Float32Array; readonly picture: PuppetPicture }
  /** A document's player and its picture (`player.picture.url`, or a character's atlas,
   *  `player.atlas.url`). */
  | { readonly player: Player; readonly picture: PuppetPicture }
  /** A layered character: its atlas is the picture; `puppet` defaults to `character.puppet()`. */
  | { readonly character: Character; readonly puppet?: Puppet }
  /** Positions computed elsewhere, e.g. by a `PuppetWorker` (`bunraku/worker`, created with
   *  `output: "float32", stride: 3`): `positions` (xyz, one triple per vertex; the worker's
   *  `positions` after `register`) becomes the position attribute's array, `triangles` (the
   *  worker's `info.triangles`) and `uvs` (`mesh.uvs`) are drawn; show each frame with
   *  `setPositions(frame.positions)`. */
  | { readonly positions: Float32Array; readonly triangles: Uint32Array; readonly uvs: Float32Array; readonly picture: PuppetPicture };

/** `PuppetMesh`'s options. */
export interface PuppetMeshOptions {
  /** Pointer pins (a puppet or a character only): pressing on the picture adds a pin there
   *  (or grabs the pin within `pinRadius`), dragging moves it. The mesh listens on the
   *  canvas of the renderer that draws it and raycasts with the camera it was last drawn
   *  with. Default false. */
  readonly pins?: boolean;
  /** How close to a pin a press grabs it, in picture pixels. Default 16. */
  readonly pinRadius?: number;
  /** Trilinear filtering with mipmaps, for a picture drawn much smaller than its pixels
   *  (a character's atlas is padded for 3 mipmap levels). Default false: bilinear, as the
   *  `Renderer` and bunraku/gl draw it. Not applied to a `THREE.Texture` you pass. */
  readonly mipmaps?: boolean;
  /** Gather the rendered mesh on the GPU from the puppet's or document's simulation mesh
   *  (`puppet.simulation`, `player.simulation`; throws without one): each frame solves and
   *  uploads only the simulation positions (`simulation`), and the vertex shader computes
   *  the rendered ones, so a picture meshed at full detail costs a frame what its
   *  simulation mesh does. `positions` then holds the rest shape (refreshed from
   *  `puppet.positions` when a pointer presses). Default false. */
  readonly gather?: boolean;
}

/** A pin move by the pointer (the `"pin"` event's payload). */
export interface PuppetPinEvent {
  /** The pin's index (as compiled). */
  readonly pin: number;
  /** Its target, in picture pixels. */
  readonly x: number;
  readonly y: number;
}

/** Events a `PuppetMesh` dispatches besides three's own. */
export interface PuppetMeshEventMap extends THREE.Object3DEventMap {
  /** A pointer added (`added: true`) or moved a pin. */
  pin: PuppetPinEvent & { readonly added: boolean };
}

const BLEND = {
  normal: [THREE.OneFactor, THREE.OneMinusSrcAlphaFactor],
  multiply: [THREE.DstColorFactor, THREE.OneMinusSrcAlphaFactor],
  screen: [THREE.OneFactor, THREE.OneMinusSrcColorFactor],
  additive: [THREE.OneFactor, THREE.OneFactor],
} as const;

function makeMaterial(texture: THREE.Texture, decode: boolean, opacity = 1, blendMode: keyof typeof BLEND = "normal"): THREE.MeshBasicMaterial {
  // Premultiplied output with bunraku/gl's blend factors: `transparent` keeps the groups in
  // their order (three sorts transparent items stably, by distance), DoubleSide keeps the
  // clockwise-on-screen triangles, depthWrite off lets overlapping parts blend by order.
  const [src, dst] = BLEND[blendMode] ?? BLEND.normal;
  const material = new THREE.MeshBasicMaterial({
    map: texture,
    side: THREE.DoubleSide,
    transparent: true,
    depthWrite: false,
    premultipliedAlpha: true,
    opacity,
    blending: THREE.CustomBlending,
    blendSrc: src,
    blendDst: dst,
  });
  // A texture made here is stored as RGBA8 (see `toTexture`) and decoded from sRGB after
  // filtering, by three's own inline decode (map_fragment's DECODE_VIDEO_TEXTURE).
  if (decode) material.defines = { DECODE_VIDEO_TEXTURE: "" };
  return material;
}

/** `material` with its vertices gathered from `simulation` (the simulation positions'
 *  texture) by the geometry's `bunrakuCorners` and `bunrakuWeights` attributes. */
function gathering(material: THREE.MeshBasicMaterial, simulation: THREE.DataTexture): THREE.MeshBasicMaterial {
  material.onBeforeCompile = (shader) => {
    shader.uniforms.bunrakuSimulation = { value: simulation };
    shader.vertexShader = shader.vertexShader
      .replace("#include <common>", `#include <common>
uniform highp sampler2D bunrakuSimulation;
attribute vec3 bunrakuCorners;
attribute vec3 bunrakuWeights;
${GATHER_GLSL}`)
      .replace("#include <begin_vertex>", "vec3 transformed = vec3(bunrakuGather(bunrakuSimulation, bunrakuCorners, bunrakuWeights), 0.0);");
  };
  material.customProgramCacheKey = () => "bunraku-gather";
  return material;
}

/** The picture as a texture set up for bunraku's uvs: `flipY = false`, `SRGBColorSpace`; one
 *  made here is filtered bilinearly (as the `Renderer` and bunraku/gl draw it), or trilinearly with
 *  `mipmaps`. A `THREE.Texture` given keeps its filters. */
function toTexture(picture: PuppetPicture, mipmaps: boolean): THREE.Texture {
  let texture: THREE.Texture;
  if (picture instanceof THREE.Texture) {
    texture = picture;
  } else {
    if ("data" in picture) {
      // ImageData or straight RGBA pixels, uploaded as they are.
      const { data, width, height } = picture;
      texture = new THREE.DataTexture(new Uint8Array(data.buffer, data.byteOffset, data.byteLength), width, height, THREE.RGBAFormat, THREE.UnsignedByteType);
    } else {
      texture = new THREE.Texture(picture as TexImageSource);
    }
    // sRGB data filtered as the Renderer and bunraku/gl filter it: between the stored
    // bytes, then decoded in the shader (`makeMaterial`). three's default for sRGB bytes,
    // SRGB8_ALPHA8, filters in linear light: up to 60/255 lighter where a dark and a light
    // texel mix (an eye's highlight), once the pose puts samples between texels.
    texture.internalFormat = "RGBA8";
    texture.magFilter = THREE.LinearFilter;
    texture.minFilter = mipmaps ? THREE.LinearMipmapLinearFilter : THREE.LinearFilter;
    texture.generateMipmaps = mipmaps;
  }
  texture.flipY = false;
  texture.colorSpace = THREE.SRGBColorSpace;
  texture.needsUpdate = true;
  return texture;
}

/**
 * A three.js `Mesh` of a bunraku puppet, document player or layered character. Its local
 * coordinates are the picture's pixels, y down, z = 0: place it with `position`, `scale`
 * (e.g. `scale.y = -1` under a y-up camera) and `rotation` like any object.
 *
 * ```ts
 * const mesh = Mesh.fromImage(pixels, width, height, { spacing: 12 });
 * const puppet = Puppet.fromMesh(mesh);
 * const sprite = new PuppetMesh({ puppet, uvs: mesh.uvs, picture: image }, { pins: true });
 * scene.add(sprite);                          // drag the picture to pin and pose it
 * // or, posed in code: puppet.compile(handles); sprite.update(targets);
 * const doc = new PuppetMesh({ player: Player.load(json), picture: image });
 * renderer.setAnimationLoop((now) => { doc.seek(now / 1000); renderer.render(scene, camera); });
 * ```
 */
export class PuppetMesh extends THREE.Mesh<THREE.BufferGeometry, THREE.MeshBasicMaterial | THREE.MeshBasicMaterial[], PuppetMeshEventMap> {
  /** The positions `[x0, y0, 0, x1, y1, 0, …]`: the position attribute's array itself,
   *  written by the solver or the player on every update (replaced only by `setPositions`). */
  readonly positions: Float32Array;
  /** The puppet posed by `update` (a puppet or a character), or null. */
  readonly puppet: Puppet | null;
  /** The player `seek` plays (a document), or null. */
  readonly player: Player | null;
  /** The texture drawn (set up: `flipY = false`, sRGB). */
  readonly texture: THREE.Texture;
  /** With `gather`, the simulation positions `[x0, y0, …]` (the start of the texture's
   *  array, written by the solver or the player on every update), else null. */
  readonly simulation: Float32Array | null = null;
  /** The pins' targets (picture pixels) that `update` last got or the pointer set. */
  targets: Float64Array = new Float64Array(0);

  private readonly attribute: THREE.BufferAttribute;
  private readonly triangles: Uint32Array;
  /** A character's parts (`[first, count]` into `triangles`), or null for one picture. */
  private readonly parts: { first: number; count: number; visible: boolean }[] | null;
  private depth: Float32Array | null = null;
  private drawOrder: Uint32Array | null = null;
  private readonly ownsTexture: boolean;
  private readonly pinOptions: { enabled: boolean; radius: number };
  private rotations: Float64Array | undefined;
  private readonly gathered: THREE.DataTexture | null = null;

  constructor(source: PuppetMeshSource, options: PuppetMeshOptions = {}) {
    let puppet: Puppet | null = null;
    let player: Player | null = null;
    let picture: PuppetPicture;
    let uvs: Float32Array;
    let triangles: Uint32Array;
    let parts: PuppetMeshPart[] | null = null;
    let order: number[] | null = null;
    let depth: Float32Array | null = null;
    let external: Float32Array | null = null; // positions computed elsewhere
    if ("character" in source) {
      const c = source.character;
      puppet = source.puppet ?? c.puppet();
      picture = c.atlas;
      uvs = c.uvs;
      // character.triangles lists the visible parts in the draw order; re-laid here part by
      // part in the parts' order, so that each part is one range (a group).
      const listed = c.triangles;
      const cparts = c.parts;
      const byName = new Map(cparts.map((p, i) => [p.name, i]));
      const drawn = c.drawOrder.map((n) => byName.get(n)!);
      const ranges = new Array<[number, number]>(cparts.length).fill([0, 0]);
      let at = 0;
      for (const i of drawn) {
        const n = cparts[i].visible === false ? 0 : cparts[i].triangles[1];
        ranges[i] = [at, n];
        at += n;
      }
      triangles = new Uint32Array(listed.length);
      let out = 0;
      parts = cparts.map((p, i) => {
        const [from, n] = ranges[i];
        triangles.set(listed.subarray(3 * from, 3 * (from + n)), 3 * out);
        const part = { name: p.name, triangles: [out, n] as [number, number], opacity: p.opacity, blendMode: p.blendMode, visible: p.visible !== false };
        out += n;
        return part;
      });
      order = drawn;
    } else if ("player" in source) {
      player = source.player;
      picture = source.picture;
      uvs = player.uvs;
      triangles = player.triangles;
      if (player.atlas) {
        const doc = player.toJSON() as { parts?: PuppetMeshPart[]; drawOrder?: (number | string)[] };
        parts = doc.parts ?? null;
        if (parts) {
          const names = new Map(parts.map((p, i) => [p.name, i]));
          order = (doc.drawOrder ?? parts.map((_, i) => i)).map((k) => (typeof k === "number" ? k : names.get(k)!));
        }
      }
      depth = parts ? null : player.triangleDepth;
    } else if ("positions" in source) {
      ({ picture, uvs, triangles, positions: external } = source);
    } else {
      puppet = source.puppet;
      picture = source.picture;
      uvs = source.uvs;
      triangles = puppet.triangles;
      depth = puppet.triangleDepth;
    }
    const count = puppet ? puppet.vertexCount : player ? player.vertexCount : uvs.length / 2;
    if (uvs.length !== 2 * count) throw new Error(`PuppetMesh: uvs has ${uvs.length} numbers, expected ${2 * count} (one [u, v] per vertex)`);

    const geometry = new THREE.BufferGeometry();
    if (external && external.length !== 3 * count) throw new Error(`PuppetMesh: positions has ${external.length} numbers, expected ${3 * count} (xyz per vertex)`);
    const positions = external ?? new Float32Array(3 * count);
    const attribute = new THREE.BufferAttribute(positions, 3).setUsage(THREE.DynamicDrawUsage);
    geometry.setAttribute("position", attribute);
    geometry.setAttribute("uv", new THREE.BufferAttribute(uvs.slice(), 2));
    geometry.setIndex(new THREE.BufferAttribute(triangles.slice(), 1));
    const ownsTexture = !(picture instanceof THREE.Texture);
    const texture = toTexture(picture, options.mipmaps === true);
    const material = parts ? parts.map((p) => makeMaterial(texture, ownsTexture, p.opacity ?? 1, p.blendMode ?? "normal")) : makeMaterial(texture, ownsTexture);
    let gathered: THREE.DataTexture | null = null;
    if (options.gather === true) {
      const simulation = (puppet ?? player!).simulation;
      if (!simulation) throw new Error("PuppetMesh: gather needs a simulation mesh (puppet.simulation or player.simulation is null)");
      const g = gatherMesh(simulation, count);
      gathered = new THREE.DataTexture(new Float32Array(2 * g.width * g.height), g.width, g.height, THREE.RGFormat, THREE.FloatType);
      gathered.userData.count = g.count;
      geometry.setAttribute("bunrakuCorners", new THREE.BufferAttribute(g.corners, 3));
      geometry.setAttribute("bunrakuWeights", new THREE.BufferAttribute(g.weights, 3));
      for (const m of Array.isArray(material) ? material : [material]) gathering(m, gathered);
    }
    super(geometry, material);
    if (gathered) {
      this.gathered = gathered;
      this.simulation = (gathered.image.data as Float32Array).subarray(0, 2 * (gathered.userData.count as number));
    }
    this.name = "PuppetMesh";
    this.positions = positions;
    this.attribute = attribute;
    this.puppet = puppet;
    this.player = player;
    this.texture = texture;
    this.ownsTexture = ownsTexture;
    this.triangles = triangles;
    this.parts = parts ? parts.map((p) => ({ first: p.triangles[0], count: p.triangles[1], visible: p.visible !== false })) : null;
    this.pinOptions = { enabled: options.pins === true, radius: options.pinRadius ?? 16 };
    if (this.pinOptions.enabled && !puppet) throw new Error("PuppetMesh: pins need a puppet or a character (a player plays its document)");

    if (order) this.setDrawOrder(order);
    if (depth) this.setDepth(depth);
    if (puppet) {
      this.targets = puppet.handles.slice();
      this.simulation?.set(puppet.simulationPositions);
      this.writePositions(puppet.positions);
    } else if (player) {
      this.seek(0);
    } else {
      this.posed();
    }
  }

  /** Shows positions computed elsewhere (a `PuppetWorker`'s `frame.positions`, xyz): the
   *  array becomes the position attribute's, with no copy, marked for upload; the bounds
   *  follow. Call it with every frame the worker gives (it writes again into the memory of
   *  the frame before last). Throws for another length. */
  setPositions(positions: Float32Array): void {
    if (!(positions instanceof Float32Array) || positions.length !== this.positions.length) {
      throw new Error(`PuppetMesh.setPositions: expected a Float32Array of ${this.positions.length} numbers (xyz per vertex)`);
    }
    (this as { positions: Float32Array }).positions = positions;
    this.attribute.array = positions;
    this.posed();
  }

  /** Poses the puppet: `puppet.updateInto(targets, positions, rotations)`, written straight
   *  into the position attribute's array, which is marked for upload; the bounds follow.
   *  Throws what `updateInto` throws (the pose is then as it was). */
  update(targets: Float64Array, rotations?: Float64Array): void {
    const puppet = this.puppet;
    if (!puppet) throw new Error("PuppetMesh.update: this mesh plays a document (seek(t))");
    const sim = this.simulation;
    if (sim) puppet.updateSimulationInto(targets, sim, rotations);
    else if (rotations) puppet.updateInto(targets, this.positions, rotations);
    else puppet.updateInto(targets, this.positions);
    if (targets !== this.targets) this.targets = targets.slice();
    this.rotations = rotations;
    this.posed();
  }

  /** Shows the document at time `t` (seconds; looped when it loops): its positions written
   *  straight into the position attribute's array, keyed overlap depths and draw order. */
  seek(t: number): void {
    const player = this.player;
    if (!player) throw new Error("PuppetMesh.seek: this mesh poses a puppet (update(targets))");
    if (this.simulation) player.simulationPositionsInto(t, this.simulation);
    else player.positionsInto(t, this.positions);
    if (this.parts) {
      const order = player.drawOrderAt(t);
      if (order && !sameOrder(order, this.drawOrder)) this.setDrawOrder(order);
    } else if (player.depthKeyed) {
      const depth = (this.depth ??= new Float32Array(player.triangleCount));
      if (player.triangleDepthInto(t, depth)) this.setDepth(depth);
    }
    this.posed();
  }

  /** New overlap depths, one per triangle (one picture): the index buffer is re-sorted so
   *  that deeper triangles are drawn later, in front (the `Renderer`'s order). */
  setDepth(depth: Float32Array): void {
    if (this.parts) return;
    const index = this.geometry.index!;
    (index.array as Uint32Array).set(hasDepth(depth) ? depthOrder(this.triangles, depth) : this.triangles);
    index.needsUpdate = true;
    if (depth !== this.depth) this.depth = depth.slice();
  }

  /** A character's draw order (part indices, bottom first): its groups in that order. */
  setDrawOrder(order: ArrayLike<number>): void {
    const parts = this.parts;
    if (!parts) return;
    const geometry = this.geometry;
    geometry.clearGroups();
    for (let k = 0; k < order.length; k++) {
      const p = parts[order[k]];
      if (p && p.visible && p.count > 0) geometry.addGroup(3 * p.first, 3 * p.count, order[k]);
    }
    this.drawOrder = Uint32Array.from(order as ArrayLike<number>);
  }

  /** Copies rest or current positions (Float64) in: at construction, and with `gather`
   *  before a pointer's raycast (not uploaded: the shader gathers). */
  private writePositions(xy: Float64Array, upload = true): void {
    const p = this.positions;
    for (let i = 0, j = 0; i < xy.length; i += 2, j += 3) {
      p[j] = xy[i];
      p[j + 1] = xy[i + 1];
      p[j + 2] = 0;
    }
    if (upload) this.posed();
  }

  /** The positions changed: upload them (with `gather`, the simulation positions), and
   *  bounds that follow the pose (the simulation mesh's, which holds the rendered one). */
  private posed(): void {
    if (this.gathered) this.gathered.needsUpdate = true;
    else this.attribute.needsUpdate = true;
    const p = this.simulation ?? this.positions;
    const stride = this.simulation ? 2 : 3;
    let minX = Infinity, minY = Infinity, maxX = -Infinity, maxY = -Infinity;
    for (let j = 0; j < p.length; j += stride) {
      const x = p[j], y = p[j + 1];
      if (x < minX) minX = x;
      if (x > maxX) maxX = x;
      if (y < minY) minY = y;
      if (y > maxY) maxY = y;
    }
    const g = this.geometry;
    const box = (g.boundingBox ??= new THREE.Box3());
    if (p.length === 0) box.makeEmpty();
    else box.set(new THREE.Vector3(minX, minY, 0), new THREE.Vector3(maxX, maxY, 0));
    box.getBoundingSphere((g.boundingSphere ??= new THREE.Sphere()));
  }

  // --- pointer pins -------------------------------------------------------------------

  private element: HTMLElement | null = null;
  private camera: THREE.Camera | null = null;
  private grabbed = -1;
  private readonly raycaster = new THREE.Raycaster();
  private readonly ndc = new THREE.Vector2();
  private readonly plane = new THREE.Plane();
  private readonly hit = new THREE.Vector3();

  override onBeforeRender(renderer: THREE.WebGLRenderer, _scene: THREE.Scene, camera: THREE.Camera): void {
    this.camera = camera;
    if (this.pinOptions.enabled && this.element !== renderer.domElement) {
      this.detach();
      this.element = renderer.domElement;
      this.element.addEventListener("pointerdown", this.onDown);
      this.element.addEventListener("pointermove", this.onMove);
      this.element.addEventListener("pointerup", this.onUp);
      this.element.addEventListener("pointercancel", this.onUp);
      this.element.style.touchAction = "none";
    }
  }

  /** Points the raycaster through the pointer; false before the mesh was drawn. */
  private aim(e: PointerEvent): boolean {
    if (!this.element || !this.camera) return false;
    const r = this.element.getBoundingClientRect();
    this.ndc.set(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
    this.raycaster.setFromCamera(this.ndc, this.camera);
    return true;
  }

  private readonly onDown = (e: PointerEvent): void => {
    if (e.button !== 0 || !this.aim(e)) return;
    const puppet = this.puppet!;
    if (this.gathered) this.writePositions(puppet.positions, false);
    const hits = this.raycaster.intersectObject(this, false);
    const first = hits[0];
    if (!first || first.face == null) return;
    const local = this.worldToLocal(first.point.clone());
    // Grab the nearest pin within reach, else add one at the rest point under the pointer.
    const t = this.targets;
    let best = -1;
    let bestD = this.pinOptions.radius;
    for (let k = 0; k < t.length / 2; k++) {
      const d = Math.hypot(t[2 * k] - local.x, t[2 * k + 1] - local.y);
      if (d <= bestD) [best, bestD] = [k, d];
    }
    let added = false;
    if (best < 0) {
      // The hit's barycentric coordinates in its posed triangle, carried to the rest shape.
      const { a, b, c } = first.face;
      const p = this.positions;
      const [ax, ay, bx, by, cx, cy] = [p[3 * a], p[3 * a + 1], p[3 * b], p[3 * b + 1], p[3 * c], p[3 * c + 1]];
      const area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
      if (area === 0) return;
      const wa = ((bx - local.x) * (cy - local.y) - (by - local.y) * (cx - local.x)) / area;
      const wb = ((cx - local.x) * (ay - local.y) - (cy - local.y) * (ax - local.x)) / area;
      const wc = 1 - wa - wb;
      const rest = puppet.vertices;
      const rx = wa * rest[2 * a] + wb * rest[2 * b] + wc * rest[2 * c];
      const ry = wa * rest[2 * a + 1] + wb * rest[2 * b + 1] + wc * rest[2 * c + 1];
      const n = puppet.handleCount;
      const handles = new Float64Array(2 * n + 2);
      handles.set(puppet.handles);
      handles[2 * n] = rx;
      handles[2 * n + 1] = ry;
      const radius = new Float64Array(n + 1);
      radius.set(puppet.radius);
      try {
        puppet.compile(handles, { kinds: [...puppet.kinds, "position"], radius });
      } catch {
        return; // e.g. too close to another pin
      }
      const targets = new Float64Array(2 * n + 2);
      targets.set(t.subarray(0, 2 * n));
      targets[2 * n] = local.x;
      targets[2 * n + 1] = local.y;
      this.targets = targets;
      const rotations = this.rotations && this.rotations.length === 2 * n ? Float64Array.from([...this.rotations, 0, 1]) : undefined;
      this.update(targets, rotations);
      best = n;
      added = true;
    }
    this.grabbed = best;
    this.element!.setPointerCapture?.(e.pointerId);
    e.preventDefault();
    this.dispatchEvent({ type: "pin", pin: best, x: this.targets[2 * best], y: this.targets[2 * best + 1], added });
  };

  private readonly onMove = (e: PointerEvent): void => {
    if (this.grabbed < 0 || !this.aim(e)) return;
    // The picture's plane (z = 0 in local space), in world space.
    this.updateWorldMatrix(true, false);
    const normal = new THREE.Vector3(0, 0, 1).transformDirection(this.matrixWorld);
    const origin = new THREE.Vector3().setFromMatrixPosition(this.matrixWorld);
    this.plane.setFromNormalAndCoplanarPoint(normal, origin);
    if (!this.raycaster.ray.intersectPlane(this.plane, this.hit)) return;
    const local = this.worldToLocal(this.hit);
    const k = this.grabbed;
    this.targets[2 * k] = local.x;
    this.targets[2 * k + 1] = local.y;
    this.update(this.targets, this.rotations);
    this.dispatchEvent({ type: "pin", pin: k, x: local.x, y: local.y, added: false });
  };

  private readonly onUp = (): void => {
    this.grabbed = -1;
  };

  private detach(): void {
    const el = this.element;
    if (!el) return;
    el.removeEventListener("pointerdown", this.onDown);
    el.removeEventListener("pointermove", this.onMove);
    el.removeEventListener("pointerup", this.onUp);
    el.removeEventListener("pointercancel", this.onUp);
    this.element = null;
  }

  /** Stops listening to the pointer and frees the geometry, the materials and the texture
   *  it made (not a `THREE.Texture` you gave it, nor the puppet or player). */
  override dispose(): void {
    this.detach();
    this.geometry.dispose();
    for (const m of Array.isArray(this.material) ? this.material : [this.material]) m.dispose();
    if (this.ownsTexture) this.texture.dispose();
    this.gathered?.dispose();
  }
}

function sameOrder(a: Uint32Array, b: Uint32Array | null): boolean {
  if (!b || a.length !== b.length) return false;
  for (let k = 0; k < a.length; k++) if (a[k] !== b[k]) return false;
  return true;
}
