// The playback build (issue 26 §12, "bunraku/player"): the wasm built without the authoring
// entry points (cargo feature `authoring` off) plays every document bit for bit as the full
// build does, with the same guard and error codes, exports nothing that authors, and is at
// least 35 % smaller gzipped.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { gzipSync } from "node:zlib";
import * as full from "bunraku";
import * as playback from "bunraku/player";

const wasm = (dir) => readFileSync(new URL(`../../${dir}/bunraku_bg.wasm`, import.meta.url));
full.initSync({ module: wasm("pkg") });
playback.initSync({ module: wasm("pkg-player") });

const asset = (name) => JSON.parse(readFileSync(new URL(`../../assets/${name}`, import.meta.url), "utf8"));
const DOCUMENTS = ["gingerbread.bunraku.json", "character-motion.bunraku.json"];

/** The bits of a Float64Array, for an exact comparison (NaN and -0 included). */
const bits = (a) => Array.from(new BigUint64Array(a.buffer, a.byteOffset, a.length));

for (const name of DOCUMENTS) {
  test(`${name}: the playback build plays it bit for bit as the full build`, () => {
    const doc = asset(name);
    const a = full.Player.load(doc);
    const b = playback.Player.load(doc);
    try {
      assert.equal(b.duration, a.duration);
      assert.equal(b.vertexCount, a.vertexCount);
      const out = [new Float64Array(2 * a.vertexCount), new Float64Array(2 * b.vertexCount)];
      // Forwards, then seeking back (dynamics from their checkpoints).
      const times = [0, 0.1, 0.37, 0.9, 1.6, 2.4, 0.05, 1.2, a.duration];
      for (const t of times) {
        a.positionsInto(t, out[0]);
        b.positionsInto(t, out[1]);
        assert.deepEqual(bits(out[1]), bits(out[0]), `positions at ${t} s`);
      }
      assert.equal(JSON.stringify(b.toJSON()), JSON.stringify(a.toJSON()), "toJSON");
    } finally {
      a.free();
      b.free();
    }
  });
}

test("the playback build exports what plays documents, and none of the authoring classes", () => {
  for (const name of ["Player", "Track", "KeyTrack", "Easing", "Rig", "ParameterSpring"]) {
    assert.equal(typeof playback[name], "function", `bunraku/player exports ${name}`);
  }
  for (const name of ["Puppet", "Mesh", "Blender", "SurfaceBlender", "Dynamics", "Character", "Renderer", "flatten", "surfaceFromOBJ"]) {
    assert.equal(playback[name], undefined, `bunraku/player does not export ${name}`);
    assert.equal(typeof full[name], "function", `bunraku exports ${name}`);
  }
});

test("the playback build refuses bad input with the same codes, and its objects are guarded", () => {
  const bad = { format: "bunraku-puppet", version: 1, mesh: { vertices: [0, 0], triangles: "no" } };
  const codeOf = (f) => {
    try {
      f();
    } catch (e) {
      return [e.code, e.message];
    }
    return null;
  };
  const [code, message] = codeOf(() => playback.Player.load(bad));
  assert.deepEqual([code, message], codeOf(() => full.Player.load(bad)));
  assert.equal(code, "bad-document");
  const player = playback.Player.load(asset("gingerbread.bunraku.json"));
  assert.equal(codeOf(() => player.positionsInto(0, new Float64Array(3)))[0], "bad-length");
  // A getter that throws while the arguments are read leaves the player usable.
  const trap = { get length() { throw new Error("no"); } };
  assert.equal(codeOf(() => player.positionsInto(0, trap))[0], "unreadable");
  player.positionsInto(0, new Float64Array(2 * player.vertexCount));
  player.free();
  assert.equal(codeOf(() => player.duration)[0], "freed");
  const track = new playback.KeyTrack(1);
  track.free();
  assert.equal(codeOf(() => track.dims)[0], "freed");
});

test("the playback build is at least 35 % smaller gzipped than the full build", (t) => {
  const [whole, lean] = ["pkg", "pkg-player"].map((dir) => gzipSync(wasm(dir), { level: 9 }).length);
  t.diagnostic(`gzip -9: full ${whole} bytes, playback ${lean} bytes (${(100 * (1 - lean / whole)).toFixed(1)} % smaller)`);
  assert.ok(lean <= 0.65 * whole, `playback ${lean} bytes against full ${whole}`);
});
