// Writes assets/character-motion.bunraku.json, the sample character's animated document
// (issue 25: "the shipped sample character turns its head by a parameter and swings an
// ear"), and its texture assets/character-atlas.png, which the document names by the
// relative URL "character-atlas.png".
//
// The character is assets/character.psd (scripts/make-sample-character.mjs) read with
// bunraku/psd and made a Character (automatic glue) at a spacing of 8 px. Its keyforms are
// poses made here with the character's own puppet (two-step method, so each is one direct
// solve): four pins hold the torso, an advanced pin with a radius holds the head rigid, and
// an advanced pin holds the ear's tip.
//
//   * `headTurn` (keys −1, 0, 1): the head and the ear turned by −HEAD_DEGREES, 0 and
//     +HEAD_DEGREES about the neck (the head pin and the ear's tip turned about NECK; the
//     neck bends between the head and the collar).
//   * `earSwing` (keys −1, 0, 1): the head at rest and the ear's tip swung by −EAR_DEGREES,
//     0 and +EAR_DEGREES about the ear's root, its tip turned EAR_CURL times that, so that
//     the ear bends.
//
// Positive values turn clockwise on screen (the document's angles are counter-clockwise in
// y-down canvas pixels). One channel keys `headTurn` with eased keys over a looping clip of
// DURATION seconds (a turn to the right, a pause, a turn to the left, a pause, back), and a
// dynamics entry of kind "parameter" (Live2D's physics) swings `earSwing` from
// `headTurn`'s motion: when the head turns one way, the ear trails the other way, then
// overshoots and settles while the head holds still.
//
// The file is kept lean: the pose positions are rounded to 1/1000 px and the uvs written
// as the shortest decimals that read back as the same 32-bit floats (the player reads uvs
// as f32), so the player sees exactly the numbers written and the document round-trips bit
// for bit. tests/node/sample-motion.test.mjs plays it.
//
//   node scripts/make-sample-motion.mjs          (after scripts/make-sample-character.mjs)

import { readFileSync, writeFileSync } from "node:fs";
import { pathToFileURL } from "node:url";
import { PNG } from "pngjs";
import { initSync, Character, KeyTrack, Player } from "bunraku";
import { readLayersFromPSD } from "bunraku/psd";
import { buildGL } from "./build-gl.mjs";

buildGL({ log: () => {} });
initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });

/** The mesh spacing, canvas pixels: 1,492 vertices (the default, about 2,400, doubles the file). */
export const SPACING = 8;
/** `headTurn` = ±1 turns the head by this much, degrees. */
export const HEAD_DEGREES = 20;
/** `earSwing` = ±1 swings the ear's tip about its root by this much, degrees. */
export const EAR_DEGREES = 30;
/** How much further than its swing the ear's tip turns (the bend). */
const EAR_CURL = 1.2;
/** The clip's length, seconds. */
export const DURATION = 3;

/** The pivot of the head's turn: the neck, just above the collar (canvas pixels). */
export const NECK = [160, 118];
/** The head pin: the face's centre, holding the face and hair rigid within HEAD_RADIUS. */
export const HEAD = [160, 66];
const HEAD_RADIUS = 34;
/** The ear's root (its glue disc is about here) and the ear pin, near its tip. */
export const EAR_ROOT = [122, 40];
export const EAR_TIP = [92, 106];
/** Torso pins: the hips and below the shoulders, so that the body stays still. */
const TORSO = [[124, 230], [196, 230], [128, 146], [192, 146]];

/** `[x, y]` turned by `degrees` about `centre` (clockwise on screen: y points down). */
function turn([x, y], degrees, [cx, cy]) {
  const a = (degrees * Math.PI) / 180;
  const [dx, dy] = [x - cx, y - cy];
  return [cx + Math.cos(a) * dx - Math.sin(a) * dy, cy + Math.sin(a) * dx + Math.cos(a) * dy];
}

/** The character from the PSD. */
export function sampleCharacter() {
  const layers = readLayersFromPSD(readFileSync(new URL("../assets/character.psd", import.meta.url)));
  return Character.fromLayers(layers, { spacing: SPACING });
}

/**
 * A pose of `character` with the head turned by `head` degrees about the neck and the ear
 * swung by `ear` degrees about its root (after the head's turn), as a Float64Array of
 * positions; checks that it has no flipped triangle and that its joints are closed.
 */
export function pose(character, head, ear) {
  const partOf = (name) => character.parts.findIndex((p) => p.name === name);
  const [torso, headPart, earPart] = [partOf("torso"), partOf("head"), partOf("ear")];
  const puppet = character.puppet({ method: "two-step" });
  puppet.compile(new Float64Array([...TORSO.flat(), ...HEAD, ...EAR_TIP]), {
    kinds: [...TORSO.map(() => "position"), "advanced", "advanced"],
    radius: new Float64Array([...TORSO.map(() => 0), HEAD_RADIUS, 0]),
    parts: [...TORSO.map(() => torso), headPart, earPart],
  });
  const root = turn(EAR_ROOT, head, NECK);
  const tip = turn(turn(EAR_TIP, head, NECK), ear, root);
  const radians = (d) => (d * Math.PI) / 180;
  const targets = new Float64Array([...TORSO.flat(), ...turn(HEAD, head, NECK), ...tip]);
  const rotations = new Float64Array([...TORSO.flatMap(() => [0, 1]), radians(head), 1, radians(head + EAR_CURL * ear), 1]);
  const positions = puppet.update(targets, rotations);
  const { flipped } = puppet.quality();
  const gap = puppet.glueGap;
  puppet.free();
  if (flipped !== 0) throw new Error(`the pose (head ${head}°, ear ${ear}°) has ${flipped} flipped triangles`);
  if (!(gap < 0.05)) throw new Error(`the pose (head ${head}°, ear ${ear}°) opens a joint by ${gap} px`);
  return positions;
}

/** The shortest decimal that reads back as the same 32-bit float as `x`. */
function shortestFloat32(x) {
  const f = Math.fround(x);
  for (let digits = 1; digits <= 9; digits++) {
    const d = Number(f.toPrecision(digits));
    if (Math.fround(d) === f) return d;
  }
  return f;
}

/** `x` rounded to 1/1000 (positions in canvas pixels). */
const milli = (x) => Math.round(x * 1000) / 1000 || 0; // no −0: JSON cannot hold it

/** `headTurn`'s keys: eased turns with still holds between them, looping at DURATION. */
export function headKeys() {
  const head = new KeyTrack(1);
  head.addKey(0, 0, { ease: "ease-in-out" }); //  turn right…
  head.addKey(0.5, 1); //                           …and hold still (linear between equal values)
  head.addKey(1.2, 1, { ease: "ease-in-out" }); // turn left…
  head.addKey(1.9, -1); //                          …and hold
  head.addKey(2.5, -1, { ease: "ease-in-out" }); // back to the middle
  head.addKey(DURATION, 0);
  const keys = head.toJSON();
  head.free();
  return keys;
}

/** The document (a plain object) and the character's atlas. */
export function makeSampleMotion() {
  const character = sampleCharacter();
  const doc = character.toDocument({ atlasUrl: "character-atlas.png", arrays: "numbers" });
  const atlas = character.atlas;
  const poses = [
    pose(character, -HEAD_DEGREES, 0),
    pose(character, HEAD_DEGREES, 0),
    pose(character, 0, -EAR_DEGREES),
    pose(character, 0, EAR_DEGREES),
  ];
  character.free();
  Object.assign(doc, {
    version: 3,
    meshing: { from: "character.psd", spacing: SPACING },
    mesh: { ...doc.mesh, uvs: doc.mesh.uvs.map(shortestFloat32) },
    poses: poses.map((p) => ({ positions: Array.from(p, milli) })),
    tick: 120,
    parameters: [
      { id: "headTurn", min: -1, max: 1, default: 0, keys: [-1, 0, 1], keyforms: [{ pose: 0 }, { pose: null }, { pose: 1 }] },
      { id: "earSwing", min: -1, max: 1, default: 0, keys: [-1, 0, 1], keyforms: [{ pose: 2 }, { pose: null }, { pose: 3 }] },
    ],
    channels: [{ target: "parameters.headTurn", keys: headKeys() }],
    dynamics: [
      { kind: "parameter", parameter: "earSwing", input: { parameter: "headTurn" }, frequency: 1.6, damping: 0.2, inertia: 1, scale: 1 },
    ],
    play: "channels",
    loop: true,
    duration: DURATION,
  });
  return { doc, atlas };
}

if (import.meta.url === pathToFileURL(process.argv[1]).href) {
  const { doc, atlas } = makeSampleMotion();
  const player = Player.load(doc); // checks every field
  player.free();
  // Kept as version 3 (plain numbers; the player would write version 4): it tests that version.
  const text = JSON.stringify(doc);
  const out = new URL("../assets/character-motion.bunraku.json", import.meta.url);
  writeFileSync(out, text);
  const png = new PNG({ width: atlas.width, height: atlas.height });
  png.data.set(atlas.data);
  const pngBytes = PNG.sync.write(png, { deflateLevel: 9 });
  writeFileSync(new URL("../assets/character-atlas.png", import.meta.url), pngBytes);
  console.log(
    `wrote assets/character-motion.bunraku.json (${doc.mesh.vertices.length / 2} vertices, ${doc.poses.length} poses, ` +
      `${(text.length / 1024).toFixed(1)} KB) and assets/character-atlas.png (${atlas.width} × ${atlas.height}, ${(pngBytes.length / 1024).toFixed(1)} KB)`,
  );
}
