// Type-level checks of the built declarations (pkg/bunraku.d.ts, and dist/gl.d.ts of the
// WebGL2 helper `bunraku/gl`), compiled with
// `tsc --strict` by tests/node/readme-types.test.mjs together with the README's snippets:
// optional parameters are optional, options and results have names and no `any`, bulk data
// are typed arrays, and errors have codes. A line marked @ts-expect-error must not compile.
import {
  Mesh,
  Player,
  Puppet,
  Renderer,
  SurfaceBlender,
  SurfaceDeformer,
  flatten,
  surfaceFromOBJ,
  surfaceQuality,
  type BunrakuError,
  type EdgeWeights,
  type ErrorCode,
  type FlattenOptions,
  type Flattening,
  type ImageOptions,
  type MeshJSON,
  type OutlineOptions,
  type Quality,
  type QualitySummary,
  type RegisterOptions,
  type RenderOptions,
  type Surface,
  type SurfaceBlendOptions,
  type SurfaceDeformOptions,
  type SurfaceQuality,
  type SurfaceRegions,
} from "bunraku";
import {
  MeshPainter,
  PuppetView,
  PuppetViewError,
  fitTransform,
  type Affine,
  type PictureSource,
  type PuppetViewErrorCode,
  type PuppetViewOptions,
} from "bunraku/gl";

/** `true` when `T` and `U` are the same type (`any` equals nothing but `any`). */
type Equal<T, U> = (<G>() => G extends T ? 1 : 2) extends <G>() => G extends U ? 1 : 2 ? true : false;
/** Compiles only when its argument is `true`. */
function check<T extends true>(): void {}

declare const v: Float64Array;
declare const t: Uint32Array;
declare const rgba: Uint8ClampedArray;

// Every options parameter is optional.
const puppet = Puppet.register(v, t);
Puppet.register(v, t, { weights: "cotangent", handleWeight: 500 });
const outline = Mesh.fromOutline(v);
Mesh.fromOutline(v, [v], { spacing: 2, minAngle: 25, maxVertices: 1000 });
Mesh.fromImage(rgba, 2, 2);
Mesh.fromImage(rgba, 2, 2, { alphaThreshold: 1, margin: 0, simplify: 0, minArea: 0 });
flatten(v, t);
flatten(v, t, { weights: "uniform", pins: t, targets: v });
const renderer = new Renderer(rgba, 2, 2);
renderer.render(v, t, new Float32Array(8), 4, 4);
renderer.renderInto(new Uint8ClampedArray(64), v, t, new Float32Array(8), 4, 4, { background: [0, 0, 0, 255] });

// Options are checked.
// @ts-expect-error: no such weighting
Puppet.register(v, t, { weights: "harmonic" });
// @ts-expect-error: a misspelt option
Puppet.register(v, t, { handleWieght: 5 });
// @ts-expect-error: an option of the wrong type
Mesh.fromImage(rgba, 2, 2, { minAngle: "30" });
// @ts-expect-error: bulk data are typed arrays
puppet.update([0, 0]);
// @ts-expect-error: bulk data are typed arrays
puppet.compile([0, 0]);

// The options parameters are the named interfaces.
check<Equal<Parameters<typeof Puppet.register>[2], RegisterOptions | undefined>>();
check<Equal<Parameters<typeof Mesh.fromOutline>[2], OutlineOptions | undefined>>();
check<Equal<Parameters<typeof Mesh.fromImage>[3], ImageOptions | undefined>>();
check<Equal<Parameters<typeof flatten>[2], FlattenOptions | undefined>>();
check<Equal<Parameters<Renderer["render"]>[5], RenderOptions | undefined>>();
check<Equal<RegisterOptions["weights"], EdgeWeights | undefined>>();

// Results have names, and no `any`.
check<Equal<typeof puppet.weights, EdgeWeights>>();
check<Equal<ReturnType<Mesh["toJSON"]>, MeshJSON>>();
check<Equal<ReturnType<Puppet["quality"]>, Quality>>();
check<Equal<ReturnType<typeof flatten>, Flattening>>();
check<Equal<ReturnType<typeof surfaceFromOBJ>, Surface>>();
check<Equal<Flattening["quality"], Quality>>();
check<Equal<Quality["edgeStrain"], QualitySummary>>();
check<Equal<Parameters<typeof Mesh.fromJSON>[0], string | MeshJSON>>();
const json: MeshJSON = outline.toJSON();
Mesh.fromJSON(json);
Mesh.fromJSON(JSON.stringify(outline));

// Errors carry codes.
try {
  puppet.compile(v);
} catch (e) {
  const error = e as BunrakuError;
  const code: ErrorCode = error.code;
  check<Equal<typeof error.index, number | undefined>>();
  check<Equal<typeof error.edge, [number, number] | undefined>>();
  // @ts-expect-error: not a code
  if (code === "handle_outside") throw error;
  if (error instanceof Error && code === "handle-outside") console.warn(error.message, error.index);
}

// Issue 27: the 3D surfaces take three.js's arrays and matrices.
const positions32 = new Float32Array(9);
const index16 = new Uint16Array(3);
const blender3 = SurfaceBlender.register(positions32, index16, { tetrisation: "face", stitch: "shape", iterations: 2 });
blender3.blendInto(new Float64Array(1), positions32);
const deformer3 = SurfaceDeformer.register(v, t, { regularization: 0.5, operator: "aligned" });
deformer3.compile({ fixed: t, handles: [t] });
deformer3.updateInto([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1], positions32);
deformer3.updateInto(new Float64Array(16), v);
check<Equal<Parameters<typeof SurfaceBlender.register>[2], SurfaceBlendOptions | undefined>>();
check<Equal<Parameters<typeof SurfaceDeformer.register>[2], SurfaceDeformOptions | undefined>>();
check<Equal<Parameters<SurfaceDeformer["compile"]>[0], SurfaceRegions>>();
check<Equal<ReturnType<typeof surfaceQuality>, SurfaceQuality>>();
check<Equal<SurfaceQuality["volumeChange"], number | null>>();
check<Equal<typeof deformer3.operator, "plain" | "aligned">>();
// @ts-expect-error: no such operator
SurfaceDeformer.register(v, t, { operator: "curved" });
// @ts-expect-error: handles are a list of Uint32Array
deformer3.compile({ handles: t });
// @ts-expect-error: the output is a typed array
deformer3.updateInto(new Float64Array(16), [0, 0, 0]);

// bunraku/gl: the pictures it takes, typed arrays, optional options, named results.
declare const canvas: HTMLCanvasElement;
declare const bitmap: ImageBitmap;
declare const image: HTMLImageElement;
declare const uvs: Float32Array;
const view = new PuppetView(canvas, bitmap, t, uvs);
new PuppetView(canvas, new ImageData(2, 2), t, uvs, { depth: null, fit: v, fill: 0.9, pixelRatio: 1, onContextLost: (lost: boolean) => void lost });
new PuppetView(canvas, image, t, uvs, { transform: [1, 0, 0, 1, 0, 0] });
check<Equal<Parameters<PuppetView["draw"]>[0], Float64Array | Float32Array>>();
check<Equal<ReturnType<PuppetView["draw"]>, boolean>>();
check<Equal<typeof view.transform, Affine>>();
check<Equal<Parameters<MeshPainter["draw"]>[1], Affine>>();
check<Equal<ConstructorParameters<typeof PuppetView>[4], PuppetViewOptions | undefined>>();
check<Equal<ConstructorParameters<typeof PuppetView>[1], PictureSource>>();
check<Equal<ReturnType<typeof fitTransform>, Affine | null>>();
// @ts-expect-error: positions are a typed array
view.draw([0, 0]);
// @ts-expect-error: a transform is six numbers
view.setTransform([1, 0, 0, 1]);
// @ts-expect-error: a misspelt option
new PuppetView(canvas, bitmap, t, uvs, { fil: 1 });
try {
  view.draw(v);
} catch (e) {
  if (e instanceof PuppetViewError) {
    const code: PuppetViewErrorCode = e.code;
    // @ts-expect-error: not a code
    if (code === "no_webgl2") throw e;
    console.warn(e.message);
  }
}

// Issue 26 §7: what the docs show type-checks. A document written into a variable (its
// literal types widened to string and number[]) loads; `render` gives what ImageData takes.
const doc = {
  format: "bunraku-puppet",
  version: 3,
  mesh: { vertices: [0, 0, 1, 0, 0, 1], triangles: [0, 1, 2] },
  pins: { points: [0, 0], kinds: ["bend"] },
  channels: [{ target: "pins[0].angle", keys: [{ t: 0, v: 0, interp: "bezier", ease: [0.42, 0, 0.58, 1] }, { t: 1, v: 1 }] }],
  play: "channels",
};
Player.load(doc);
// @ts-expect-error: a document is an object or its text
Player.load(42);
const frame = new Renderer(rgba, 2, 2).render(v, t, new Float32Array(2 * v.length / 2), 2, 2);
new ImageData(frame, 2, 2);
// Float32Array outputs (issue 26 §6).
const gpu = new Float32Array(3 * 4);
Puppet.register(v, t).updateInto(v, gpu);
