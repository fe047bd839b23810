// `bunraku/pixi`: `PuppetSprite`, a PixiJS v8 display object that draws a puppet, a played
// document or a layered character. It is a Pixi `Mesh` whose `MeshGeometry` positions
// buffer holds the very `Float32Array` the solver writes into (`puppet.updateInto`,
// `player.positionsInto`): each frame the wasm writes the positions there and the buffer
// is only marked for upload, with no copy of ours. pixi.js (≥ 8) is a peer dependency,
// imported as a bare specifier and never bundled. With `gather`, the rendered mesh is
// gathered on the GPU from its simulation mesh (a custom GL program; js/gl/gather.ts).

import { BufferImageSource, compileHighShaderGl, fragmentGlTemplate, GlProgram, globalUniformsBitGl, localUniformBitGl, Mesh, MeshGeometry, Rectangle, roundPixelsBitGl, Shader, Texture, textureBitGl, Ticker, vertexGlTemplate, type FederatedPointerEvent, type Buffer } from "pixi.js";
import { Character, Player, Puppet, type SimulationMesh } from "./index.js";
import { depthOrder } from "./gl/depth.js";
import { GATHER_GLSL, gatherMesh } from "./gl/gather.js";

/** What a `PuppetSprite` draws: a compiled or uncompiled `Puppet`, a `Player` (a loaded
 *  document) or a layered `Character` (its own puppet is made unless `options.puppet`). */
export type PuppetSpriteSource = Puppet | Player | Character | PuppetSpritePositions;

/** Positions computed elsewhere, e.g. by a `PuppetWorker` (`bunraku/worker`, created with
 *  `output: "float32"`): `positions` (xy, the worker's `positions` after `register`) becomes
 *  the geometry's positions buffer, `triangles` (the worker's `info.triangles`) are drawn with
 *  `options.texture` and `options.uvs` (required); show each frame with
 *  `setPositions(frame.positions)`. */
export interface PuppetSpritePositions {
  readonly positions: Float32Array;
  readonly triangles: Uint32Array;
}

/** `new PuppetSprite(source, options)`'s options. */
export interface PuppetSpriteOptions {
  /** The picture (a puppet's, a document's `picture` or a character document's atlas), as a
   *  Pixi `Texture` (e.g. `await Assets.load(url)`), not flipped: bunraku's uvs are v-down,
   *  as Pixi's. Required but for a `Character`, whose atlas is made into one when left out. */
  texture?: Texture;
  /** A puppet's uvs, one `[u, v]` per vertex (e.g. `mesh.uvs`). Default: the rest vertices
   *  over the texture's size (a mesh made from the picture, in its pixels). */
  uvs?: Float32Array;
  /** A `Character`'s puppet (default: `character.puppet()`, owned and freed by the sprite). */
  puppet?: Puppet;
  /** Pointer pins (a puppet or a character): a press on the shape pins it there (compiling
   *  the pins again) or grabs the pin within `pinRadius`, and a drag moves that pin. */
  pins?: boolean;
  /** How near (in the sprite's local units, i.e. picture pixels) a press must be to grab a
   *  pin. Default 12. */
  pinRadius?: number;
  /** A player: play on the ticker (`time` advances by its `deltaMS` times `speed`). Default
   *  false (call `seek(t)` or set `time` yourself). */
  autoplay?: boolean;
  /** Playback rate. Default 1. */
  speed?: number;
  /** The ticker for `autoplay` and for pins (which keep solving on it while the injective
   *  method has not converged). Default `Ticker.shared`. */
  ticker?: Ticker;
  /** Gather the rendered mesh on the GPU from the puppet's or document's simulation mesh
   *  (`puppet.simulation`, `player.simulation`; throws without one): each frame solves and
   *  uploads only the simulation positions (`simulation`, a small float texture) and the
   *  vertex shader computes the rendered ones. WebGL renderers only. `positions` then holds
   *  the rest shape (refreshed from `puppet.positions` when a pointer presses), the hit area
   *  is the simulation mesh's bounding box, and the geometry's bounds stay the rest shape's.
   *  Default false. */
  gather?: boolean;
}

/** A part of a character document (`PuppetDocument.parts`), as far as the sprite reads it. */
interface DocPart {
  triangles: [number, number];
  visible?: boolean;
}

/**
 * A Pixi v8 display object drawing a bunraku puppet, document or layered character: a
 * `Mesh` over a `MeshGeometry` whose positions are written by the solver in place.
 *
 * ```ts
 * await init();
 * const mesh = BunrakuMesh.fromImage(pixels.data, pixels.width, pixels.height);
 * const puppet = Puppet.fromMesh(mesh);
 * const sprite = new PuppetSprite(puppet, { texture, uvs: mesh.uvs, pins: true });
 * app.stage.addChild(sprite);                        // press to pin, drag to pose
 *
 * const player = Player.load(await (await fetch("walk.bunraku.json")).json());
 * app.stage.addChild(new PuppetSprite(player, { texture: await Assets.load("walk.png"), autoplay: true }));
 * ```
 *
 * It handles:
 * - bunraku's conventions: positions in picture pixels, y down (the sprite's local space);
 *   uvs v-down (the texture is not flipped); triangles of either winding (the mesh's state
 *   does not cull, Pixi's default, kept);
 * - overlap depth (`puppet.setOverlap`, a document's overlap regions and keyed depths): the
 *   triangles are drawn sorted by depth, the index buffer sorted again only when the depths
 *   change;
 * - a character's parts in their draw order (a `Character`'s, a document's keyed
 *   `drawOrderTrack`), the index buffer rewritten only when the order changes. Parts are
 *   drawn with normal blending at full opacity (their `opacity` and `blendMode` are not
 *   applied: `bunraku/gl`'s `CharacterView` does).
 */
export class PuppetSprite extends Mesh {
  /** The positions the GPU draws, `[x0, y0, …]` (Float32, stride 2): the geometry's
   *  positions buffer's own array, which `updateInto` and `positionsInto` write. */
  readonly positions: Float32Array;
  /** The puppet posed (a `Puppet` source, or a character's), else null. */
  readonly puppet: Puppet | null;
  /** The player played (a `Player` source), else null. */
  readonly player: Player | null;
  /** Playback rate of `autoplay`. */
  speed: number;
  /** Whether `autoplay` advances `time` on the ticker (`play()`, `pause()`). */
  playing: boolean;
  /** The pins' targets `[x0, y0, …]` when `pins` is on (where the pointer put them). */
  pinTargets: Float64Array = new Float64Array(0);
  /** With `gather`, the simulation positions `[x0, y0, …]` (the start of the float
   *  texture's array, written by the solver or the player on every update), else null. */
  readonly simulation: Float32Array | null = null;
  private readonly gathered: BufferImageSource | null = null;

  private readonly triangles: Uint32Array; // drawing order before depth sorting
  private readonly indices: Uint32Array; // the index buffer's own array
  private readonly positionBuffer: Buffer;
  private readonly indexBuffer: Buffer;
  private readonly ownsPuppet: boolean;
  private readonly ticker: Ticker;
  private depth: Float32Array | null = null; // the depths the index buffer is sorted by
  private readonly depthScratch: Float32Array | null = null; // a keyed document's
  private readonly parts: DocPart[] | null = null; // a character document's
  private readonly layered: boolean; // a character or a character's document: drawn in part order
  private drawOrder: Uint32Array | null = null;
  private t = 0;
  private readonly pinRadius: number;
  private grabbed = -1;
  private readonly grab = { x: 0, y: 0 }; // the grabbed pin's target minus the pointer
  private ticking = false;

  constructor(source: PuppetSpriteSource, options: PuppetSpriteOptions = {}) {
    let puppet: Puppet | null = null;
    let player: Player | null = null;
    let texture = options.texture;
    let uvs: Float32Array;
    let triangles: Uint32Array;
    let parts: DocPart[] | null = null;
    let ownsPuppet = false;
    let external: Float32Array | null = null; // positions computed elsewhere
    if (source instanceof Player) {
      player = source;
      uvs = player.uvs;
      const doc = player.atlas ? (player.toJSON() as { parts?: DocPart[] }) : null;
      parts = doc?.parts ?? null;
      triangles = parts ? partTriangles(player.triangles, parts, player.drawOrderAt(0)) : player.triangles;
    } else if (source instanceof Character) {
      puppet = options.puppet ?? source.puppet();
      ownsPuppet = !options.puppet;
      uvs = source.uvs;
      triangles = source.triangles;
      texture ??= atlasTexture(source.atlas);
    } else if (source instanceof Puppet) {
      puppet = source;
      triangles = puppet.triangles;
      if (options.uvs) uvs = options.uvs;
      else {
        if (!texture) throw new TypeError("PuppetSprite: a puppet needs options.texture");
        const rest = puppet.vertices;
        const w = texture.width;
        const h = texture.height;
        uvs = new Float32Array(rest.length);
        for (let i = 0; i < rest.length; i += 2) {
          uvs[i] = rest[i] / w;
          uvs[i + 1] = rest[i + 1] / h;
        }
      }
    } else if (source && source.positions instanceof Float32Array) {
      if (!options.uvs) throw new TypeError("PuppetSprite: positions computed elsewhere need options.uvs");
      triangles = source.triangles;
      uvs = options.uvs;
      external = source.positions;
    } else {
      throw new TypeError("PuppetSprite: the source is not a Puppet, a Player or a Character");
    }
    if (!texture) throw new TypeError("PuppetSprite: options.texture is required for a puppet or a player");
    const n = uvs.length / 2;
    if (external && external.length !== 2 * n) throw new TypeError(`PuppetSprite: positions has ${external.length} numbers, expected ${2 * n} (xy per vertex)`);
    const positions = external ?? new Float32Array(2 * n);
    if (player) player.positionsInto(0, positions);
    else if (puppet) positions.set(puppet.positions);
    const indices = new Uint32Array(triangles);
    const geometry = new MeshGeometry({ positions, uvs: new Float32Array(uvs), indices });
    // Drawn from its own buffers (a batched mesh is copied into the batcher's).
    geometry.batchMode = "no-batch";
    const gathered = options.gather ? gatherSource((player ?? puppet!).simulation, geometry, texture) : null;
    super(gathered ? { geometry, texture, shader: gathered.shader } : { geometry, texture });
    if (gathered) {
      this.gathered = gathered.source;
      this.simulation = gathered.simulation;
      this.hitArea = new Rectangle();
      if (puppet) {
        this.simulation.set(puppet.simulationPositions);
        this.uploaded();
      }
    }
    this.state.culling = false; // bunraku's triangles are clockwise on a y-down screen
    this.positions = positions;
    this.positionBuffer = geometry.getBuffer("aPosition");
    this.indexBuffer = geometry.indexBuffer;
    this.indices = indices;
    this.triangles = triangles;
    this.puppet = puppet;
    this.player = player;
    this.ownsPuppet = ownsPuppet;
    this.parts = parts;
    this.layered = parts !== null || source instanceof Character;
    this.speed = options.speed ?? 1;
    this.playing = !!options.autoplay && !!player;
    this.ticker = options.ticker ?? Ticker.shared;
    this.pinRadius = options.pinRadius ?? 12;
    if (player) {
      if (parts) this.drawOrder = player.drawOrderAt(0);
      else {
        if (player.depthKeyed) this.depthScratch = new Float32Array(player.triangleCount);
        this.setDepth(player.triangleDepth);
      }
      this.seek(0);
    } else if (puppet && !(source instanceof Character)) {
      this.setDepth(puppet.triangleDepth);
    }
    if (options.pins && puppet) this.enablePins(puppet);
    if (this.playing || options.pins) {
      this.ticker.add(this.tick, this);
      this.ticking = true;
    }
  }

  /** Poses the puppet: `puppet.updateInto(targets, this.positions, rotations)`, then marks
   *  the positions for upload (no copy). */
  update(targets: Float64Array, rotations?: Float64Array): void {
    const puppet = this.puppet;
    if (!puppet) throw new TypeError("PuppetSprite.update: this sprite plays a document (use seek)");
    if (this.simulation) puppet.updateSimulationInto(targets, this.simulation, rotations);
    else if (rotations) puppet.updateInto(targets, this.positions, rotations);
    else puppet.updateInto(targets, this.positions);
    this.uploaded();
  }

  /** The positions (or with `gather`, the simulation positions) are marked for upload. */
  private uploaded(): void {
    const sim = this.simulation;
    if (!sim) return this.positionBuffer.update();
    this.gathered!.update();
    let minX = Infinity, minY = Infinity, maxX = -Infinity, maxY = -Infinity;
    for (let j = 0; j < sim.length; j += 2) {
      minX = Math.min(minX, sim[j]);
      maxX = Math.max(maxX, sim[j]);
      minY = Math.min(minY, sim[j + 1]);
      maxY = Math.max(maxY, sim[j + 1]);
    }
    const area = this.hitArea as Rectangle;
    area.x = minX;
    area.y = minY;
    area.width = maxX - minX;
    area.height = maxY - minY;
  }

  /** Shows positions computed elsewhere (a `PuppetWorker`'s `frame.positions`, xy): the array
   *  becomes the geometry's positions buffer's, with no copy, marked for upload. Call it
   *  with every frame the worker gives (it writes again into the memory of the frame before
   *  last). Throws for another length. */
  setPositions(positions: Float32Array): void {
    if (!(positions instanceof Float32Array) || positions.length !== this.positions.length) {
      throw new TypeError(`PuppetSprite.setPositions: expected a Float32Array of ${this.positions.length} numbers (xy per vertex)`);
    }
    (this as { positions: Float32Array }).positions = positions;
    this.positionBuffer.data = positions;
  }

  /** A player's time in seconds (setting it seeks). */
  get time(): number {
    return this.t;
  }

  set time(t: number) {
    this.seek(t);
  }

  /** Shows a player's frame at `t` seconds: its positions, keyed depths and draw order. */
  seek(t: number): void {
    const player = this.player;
    if (!player) throw new TypeError("PuppetSprite.seek: this sprite poses a puppet (use update)");
    this.t = t;
    if (this.simulation) player.simulationPositionsInto(t, this.simulation);
    else player.positionsInto(t, this.positions);
    this.uploaded();
    if (this.depthScratch && player.triangleDepthInto(t, this.depthScratch)) this.setDepth(this.depthScratch);
    if (this.parts) {
      const order = player.drawOrderAt(t);
      if (order && !sameOrder(order, this.drawOrder)) {
        this.drawOrder = order;
        this.indices.set(partTriangles(player.triangles, this.parts, order));
        this.indexBuffer.update();
      }
    }
  }

  /** Starts `autoplay` playback on the ticker. */
  play(): void {
    this.playing = true;
    if (!this.ticking) {
      this.ticker.add(this.tick, this);
      this.ticking = true;
    }
  }

  /** Stops advancing `time`. */
  pause(): void {
    this.playing = false;
  }

  /**
   * Draws the triangles in order of `depth` (one per triangle, e.g. `puppet.triangleDepth`
   * after `puppet.setOverlap`): larger in front where the shape overlaps itself. The index
   * buffer is sorted again only when the values differ from the last ones given. A
   * character (or a character's document) is drawn in its parts' draw order instead, and
   * ignores this.
   */
  setDepth(depth: Float32Array): void {
    if (this.layered) return;
    const old = this.depth;
    if (old && old.length === depth.length && old.every((d, i) => d === depth[i])) return;
    const flat = depth.every((d) => d === depth[0]);
    if (!old && flat) {
      this.depth = new Float32Array(depth);
      return;
    }
    this.depth = new Float32Array(depth);
    this.indices.set(flat ? this.triangles : depthOrder(this.triangles, depth));
    this.indexBuffer.update();
  }

  private tick(ticker: Ticker): void {
    if (this.player && this.playing) {
      const player = this.player;
      let t = this.t + (ticker.deltaMS / 1000) * this.speed;
      if (player.loop && player.duration > 0) t %= player.duration;
      else t = Math.min(t, player.duration);
      this.seek(t);
    }
    // The injective method continues towards the targets on idle frames.
    const puppet = this.puppet;
    if (puppet && puppet.handleCount > 0 && this.pinTargets.length === 2 * puppet.handleCount && !puppet.converged) {
      this.update(this.pinTargets);
    }
  }

  private enablePins(puppet: Puppet): void {
    if (puppet.handleCount > 0) this.pinTargets = puppet.pinPositions;
    this.eventMode = "static";
    this.cursor = "pointer";
    this.on("pointerdown", this.press, this);
    this.on("globalpointermove", this.move, this);
    this.on("pointerup", this.release, this);
    this.on("pointerupoutside", this.release, this);
  }

  private press(e: FederatedPointerEvent): void {
    const puppet = this.puppet!;
    if (this.simulation) this.positions.set(puppet.positions); // for `restPoint` (not uploaded)
    const { x, y } = this.toLocal(e.global);
    const targets = this.pinTargets;
    let best = -1;
    let bestD = this.pinRadius * this.pinRadius;
    for (let k = 0; 2 * k < targets.length; k++) {
      const d = (targets[2 * k] - x) ** 2 + (targets[2 * k + 1] - y) ** 2;
      if (d <= bestD) {
        best = k;
        bestD = d;
      }
    }
    if (best < 0) {
      const rest = this.restPoint(x, y);
      if (!rest) return;
      const handles = new Float64Array(puppet.handleCount * 2 + 2);
      handles.set(puppet.handles);
      handles.set(rest, handles.length - 2);
      try {
        puppet.compile(handles);
      } catch {
        return; // off the shape, or on an existing pin
      }
      const next = new Float64Array(handles.length);
      next.set(targets.subarray(0, handles.length - 2));
      next[handles.length - 2] = x;
      next[handles.length - 1] = y;
      this.pinTargets = next;
      best = handles.length / 2 - 1;
    }
    this.grabbed = best;
    this.grab.x = this.pinTargets[2 * best] - x;
    this.grab.y = this.pinTargets[2 * best + 1] - y;
    this.update(this.pinTargets);
  }

  private move(e: FederatedPointerEvent): void {
    if (this.grabbed < 0) return;
    const { x, y } = this.toLocal(e.global);
    this.pinTargets[2 * this.grabbed] = x + this.grab.x;
    this.pinTargets[2 * this.grabbed + 1] = y + this.grab.y;
    this.update(this.pinTargets);
  }

  private release(): void {
    this.grabbed = -1;
  }

  /** The rest point under the drawn point `(x, y)`: the topmost drawn triangle holding it,
   *  its barycentric weights applied to the rest vertices; null off the shape. */
  private restPoint(x: number, y: number): [number, number] | null {
    const p = this.positions;
    const tri = this.indices;
    const rest = this.puppet!.vertices;
    for (let k = tri.length - 3; k >= 0; k -= 3) {
      const a = tri[k], b = tri[k + 1], c = tri[k + 2];
      const ax = p[2 * a], ay = p[2 * a + 1];
      const v0x = p[2 * b] - ax, v0y = p[2 * b + 1] - ay;
      const v1x = p[2 * c] - ax, v1y = p[2 * c + 1] - ay;
      const det = v0x * v1y - v0y * v1x;
      if (det === 0) continue;
      const wx = x - ax, wy = y - ay;
      const s = (wx * v1y - wy * v1x) / det;
      const t = (v0x * wy - v0y * wx) / det;
      if (s < 0 || t < 0 || s + t > 1) continue;
      const r = 1 - s - t;
      return [r * rest[2 * a] + s * rest[2 * b] + t * rest[2 * c], r * rest[2 * a + 1] + s * rest[2 * b + 1] + t * rest[2 * c + 1]];
    }
    return null;
  }

  /** Stops listening to the ticker and frees a character's puppet made here (the texture
   *  is destroyed only with `{ texture: true }`, as for any Pixi mesh). */
  override destroy(options?: Parameters<Mesh["destroy"]>[0]): void {
    if (this.ticking) this.ticker.remove(this.tick, this);
    this.ticking = false;
    if (this.ownsPuppet) this.puppet?.free();
    super.destroy(options);
  }
}

/** The GL program that gathers each vertex from the simulation positions' texture. */
const GATHER_BIT = {
  name: "bunraku-gather",
  vertex: {
    header: `uniform highp sampler2D uSimulation;\nin vec3 aCorners;\nin vec3 aWeights;\n${GATHER_GLSL}`,
    start: "position = bunrakuGather(uSimulation, aCorners, aWeights);",
  },
};

/** `simulation`'s gather for a sprite of `geometry` drawn with `texture`: the attributes
 *  added to the geometry, the float texture's source (its array's start is `simulation`)
 *  and the shader. Throws without a simulation mesh. */
function gatherSource(simulation: SimulationMesh | null, geometry: MeshGeometry, texture: Texture) {
  if (!simulation) throw new TypeError("PuppetSprite: gather needs a simulation mesh (puppet.simulation or player.simulation is null)");
  const g = gatherMesh(simulation, geometry.positions.length / 2);
  geometry.addAttribute("aCorners", { buffer: g.corners, format: "float32x3" });
  geometry.addAttribute("aWeights", { buffer: g.weights, format: "float32x3" });
  const data = new Float32Array(2 * g.width * g.height);
  const source = new BufferImageSource({ resource: data, width: g.width, height: g.height, format: "rg32float", scaleMode: "nearest", autoGenerateMipmaps: false });
  // Pixi's mesh program with the gather, as GLSL ES 3.00 (texelFetch): Pixi compiles a
  // program as 3.00 when its source says so.
  const bits = [globalUniformsBitGl, localUniformBitGl, textureBitGl, roundPixelsBitGl, GATHER_BIT];
  const { vertex, fragment } = compileHighShaderGl({ template: { vertex: vertexGlTemplate, fragment: fragmentGlTemplate }, bits });
  const glProgram = new GlProgram({ name: "bunraku-gather", vertex: `#version 300 es\n${vertex}`, fragment: `#version 300 es\n${fragment}` });
  const shader: Shader & { texture: Texture } = Object.assign(new Shader({
    glProgram,
    resources: {
      uTexture: texture.source,
      uSampler: texture.source.style,
      textureUniforms: { uTextureMatrix: { type: "mat3x3<f32>", value: texture.textureMatrix.mapCoord } },
      uSimulation: source,
    },
  }), { texture });
  return { shader, source, simulation: data.subarray(0, 2 * g.count) };
}

/** The visible parts' triangles of a character document, part by part in `order`. */
function partTriangles(all: Uint32Array, parts: DocPart[], order: Uint32Array | null): Uint32Array {
  const sequence = order ? Array.from(order) : parts.map((_, i) => i);
  const count = sequence.reduce((sum, i) => sum + (parts[i].visible === false ? 0 : parts[i].triangles[1]), 0);
  const out = new Uint32Array(3 * count);
  let at = 0;
  for (const i of sequence) {
    if (parts[i].visible === false) continue;
    const [first, n] = parts[i].triangles;
    out.set(all.subarray(3 * first, 3 * (first + n)), at);
    at += 3 * n;
  }
  return out;
}

function sameOrder(a: Uint32Array, b: Uint32Array | null): boolean {
  return b !== null && a.length === b.length && a.every((v, i) => v === b[i]);
}

/** A character's atlas (straight RGBA) as a Pixi texture, through a canvas. */
function atlasTexture(atlas: { data: Uint8ClampedArray; width: number; height: number }): Texture {
  const canvas = document.createElement("canvas");
  canvas.width = atlas.width;
  canvas.height = atlas.height;
  canvas.getContext("2d")!.putImageData(new ImageData(new Uint8ClampedArray(atlas.data), atlas.width, atlas.height), 0, 0);
  return Texture.from(canvas);
}
