// Easing and KeyTrack from JavaScript (issue 25): the golden values' bits in wasm as natively,
// the CSS keywords and handles, keys exact at their times, hold exact at the next key, angles
// never wrapped, scales in log space, JSON round trips bit for bit, and coded errors that leave
// the track as it was.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Easing, KeyTrack } from "bunraku";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const codeOf = (f) => { try { f(); } catch (e) { return e.code; } return null; };
const bits = (x) => { const b = new DataView(new ArrayBuffer(8)); b.setFloat64(0, x); return b.getBigUint64(0).toString(16).padStart(16, "0"); };

test("every golden value has the same bits in wasm as natively", () => {
  const { cases } = JSON.parse(readFileSync(new URL("../fixtures/easing-golden.json", import.meta.url), "utf8"));
  assert.ok(cases.length > 500);
  const curves = new Map();
  for (const { curve, x, y } of cases) {
    if (!curves.has(curve)) curves.set(curve, Easing.parse(curve));
    assert.equal(bits(curves.get(curve).at(x)), y, `${curve} at ${x}`);
  }
  const xs = new Float64Array(cases.filter((c) => c.curve === "ease").map((c) => c.x));
  const out = new Float64Array(xs.length);
  curves.get("ease").atInto(xs, out);
  assert.deepEqual([...out].map(bits), cases.filter((c) => c.curve === "ease").map((c) => c.y), "atInto as at");
  for (const c of curves.values()) c.free();
});

test("keywords, handles and their text", () => {
  const e = Easing.parse("ease-in-out");
  assert.equal(e.at(0), 0);
  assert.equal(e.at(1), 1);
  assert.ok(Math.abs(e.at(0.5) - 0.5) < 1e-15);
  assert.equal(e.toString(), "ease-in-out");
  assert.deepEqual(e.handles, [0.42, 0, 0.58, 1]);
  const over = Easing.cubicBezier(0.3, -0.4, 0.7, 1.4);
  assert.ok(Math.max(...[0.8, 0.85, 0.9, 0.95].map((x) => over.at(x))) > 1, "y free: overshoot");
  assert.equal(Easing.parse(over.toString()).at(0.37), over.at(0.37), "its text reads back to the same curve");
  assert.equal(Easing.parse("hold").at(0.999), 0);
  assert.equal(Easing.parse("hold").handles, undefined);
  for (const [f, code] of [
    [() => Easing.cubicBezier(1.5, 0, 0.5, 1), "bad-option"],
    [() => Easing.cubicBezier(-0.1, 0, 0.5, 1), "bad-option"],
    [() => Easing.cubicBezier("0.5", 0, 0.5, 1), "bad-type"],
    [() => Easing.parse("bounce"), "bad-option"],
    [() => Easing.parse(3), "bad-type"],
    [() => e.at(NaN), "non-finite"],
    [() => e.at("0.5"), "bad-type"],
    [() => e.atInto(new Float64Array(2), new Float64Array(3)), "bad-length"],
  ]) assert.equal(codeOf(f), code, f.toString());
  const x1 = (() => { try { Easing.cubicBezier(1.5, 0, 0.5, 1); } catch (err) { return err; } })();
  assert.match(x1.message, /x1/);
  for (const c of [e, over]) c.free();
});

test("keys are exact at their times, hold is exact at the next key, angles never wrap", () => {
  const k = new KeyTrack(1);
  const ease = Easing.parse("ease-in");
  k.addKey(0, 0.1, { ease });
  k.addKey(1, 30.3, { interp: "hold" });
  k.addKey(2, 5 * Math.PI);                      // 2.5 turns
  k.addKey(3, -0.7, { ease: [0.1, -1, 0.9, 2] });
  k.addKey(4, 1 / 3);
  const out = new Float64Array(1);
  for (const [t, v] of [[0, 0.1], [1, 30.3], [2, 5 * Math.PI], [3, -0.7], [4, 1 / 3], [-5, 0.1], [9, 1 / 3]]) {
    k.valueInto(t, out);
    assert.equal(out[0], v, `at ${t}`);
  }
  k.valueInto(1.999999, out);
  assert.equal(out[0], 30.3, "held");
  k.valueInto(0.5, out);
  assert.equal(out[0], 0.1 + (30.3 - 0.1) * ease.at(0.5), "eased by the key that leaves");
  k.valueInto(2.5, out);
  assert.ok(out[0] > Math.PI && out[0] < 5 * Math.PI, "between 2.5 turns and the next key, unwrapped");
  assert.equal(k.length, 5);
  assert.deepEqual([...k.times], [0, 1, 2, 3, 4]);
  ease.free();
  k.free();
});

test("scales interpolate in log space; pin targets have two numbers", () => {
  const s = new KeyTrack(1, { space: "log" });
  s.addKey(0, 0.5);
  s.addKey(1, 2);
  const out = new Float64Array(1);
  s.valueInto(0.5, out);
  assert.ok(Math.abs(out[0] - 1) < 4e-16, `${out[0]}`);
  assert.equal(codeOf(() => s.addKey(2, 0)), "bad-option", "a scale is > 0");
  const p = new KeyTrack(2);
  p.addKey(0, [120, 40]);
  p.addKey(1, new Float64Array([160, 30]), { ease: "ease-out" });
  const xy = new Float64Array(2);
  p.valueInto(0.25, xy);
  assert.deepEqual([...xy], [130, 37.5]);
  assert.equal(codeOf(() => p.addKey(2, 5)), "bad-length");
  for (const x of [s, p]) x.free();
});

test("toJSON round-trips bit for bit, keywords as written", () => {
  const k = new KeyTrack(2);
  k.addKey(0, [0.1, 0.2], { ease: "ease-in-out" });
  k.addKey(0.8, [Math.PI, -1e-300], { ease: [0.42, 0, 0.58, 1] });
  k.addKey(1.5, [1 / 3, 2 / 3], { interp: "hold" });
  k.addKey(2, [1, 1]);
  const json = JSON.parse(JSON.stringify(k));
  assert.deepEqual(json[0], { t: 0, v: [0.1, 0.2], interp: "bezier", ease: "ease-in-out" });
  assert.deepEqual(json[2], { t: 1.5, v: [1 / 3, 2 / 3], interp: "hold" });
  const back = KeyTrack.fromJSON(json);
  assert.deepEqual(back.toJSON(), k.toJSON());
  const again = KeyTrack.fromJSON(JSON.stringify(k));
  const [a, b] = [new Float64Array(2), new Float64Array(2)];
  for (let t = -0.5; t <= 2.5; t += 0.0625) {
    k.valueInto(t, a);
    again.valueInto(t, b);
    assert.deepEqual(b, a);
  }
  const bad = (keys) => codeOf(() => KeyTrack.fromJSON(keys));
  assert.equal(bad([{ t: 0, v: 0, ease: [1.5, 0, 0.5, 1] }, { t: 1, v: 1 }]), "bad-document");
  assert.equal(bad([{ t: 1, v: 0 }, { t: 0, v: 1 }]), "bad-document");
  assert.equal(bad([{ t: 0, v: "0" }]), "bad-document");
  const e = (() => { try { KeyTrack.fromJSON([{ t: 0, v: 0, interp: "bezier", ease: [0, 0, 2, 1] }, { t: 1, v: 1 }]); } catch (err) { return err; } })();
  assert.match(e.message, /keys\[0\]\.ease/);
  assert.equal(KeyTrack.fromJSON([], { dims: 3 }).dims, 3);
  for (const x of [k, back, again]) x.free();
});

test("bad keys are coded errors that leave the track as it was", () => {
  const k = new KeyTrack(1);
  k.addKey(0, 1);
  k.addKey(1, 2);
  const before = JSON.stringify(k);
  for (const [f, code] of [
    [() => k.addKey(NaN, 1), "bad-time"],
    [() => k.addKey(0.5, NaN), "non-finite"],
    [() => k.addKey("0.5", 1), "bad-type"],
    [() => k.addKey(0.5, "1"), "bad-type"],
    [() => k.addKey(0.5, 1, { interp: "bezier" }), "bad-option"],
    [() => k.addKey(0.5, 1, { interp: "cubic" }), "bad-option"],
    [() => k.addKey(0.5, 1, { ease: "bounce" }), "bad-option"],
    [() => k.addKey(0.5, 1, { ease: [0, 0, 1] }), "bad-type"],
    [() => k.addKey(0.5, 1, { easing: "ease" }), "bad-option"],
    [() => k.removeKey(5), "bad-option"],
    [() => k.valueInto(0.5, new Float64Array(2)), "bad-length"],
    [() => new KeyTrack(0), "bad-option"],
    [() => new KeyTrack(17), "bad-option"],
    [() => new KeyTrack(1, { space: "exp" }), "bad-option"],
  ]) assert.equal(codeOf(f), code, f.toString());
  assert.equal(JSON.stringify(k), before);
  assert.equal(codeOf(() => new KeyTrack(1).valueInto(0, new Float64Array(1))), "empty-track");
  k.free();
});
