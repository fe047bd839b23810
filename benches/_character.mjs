// The test character of src/meshing/image.rs (`bunraku::meshing::test_character`) drawn
// in JavaScript, shared by the wasm benchmarks; the leading "_" keeps it out of the test
// runner's files.

/** The test character of src/meshing/image.rs, as RGBA. */
export function character(w, h) {
  const s = Math.min(w, h);
  const capsule = (px, py, ax, ay, bx, by, r) => {
    const [abx, aby, apx, apy] = [bx - ax, by - ay, px - ax, py - ay];
    const t = Math.min(1, Math.max(0, (apx * abx + apy * aby) / (abx * abx + aby * aby)));
    return Math.hypot(apx - t * abx, apy - t * aby) - r;
  };
  const disc = (px, py, cx, cy, r) => Math.hypot(px - cx, py - cy) - r;
  const rgba = new Uint8ClampedArray(w * h * 4);
  for (let y = 0; y < h; y++)
    for (let x = 0; x < w; x++) {
      const [px, py] = [(x + 0.5) / s, (y + 0.5) / s];
      const ellipse = (Math.hypot((px - 0.5) / 0.15, (py - 0.5) / 0.19) - 1) * 0.15;
      let d = Math.min(
        disc(px, py, 0.5, 0.2, 0.11),
        capsule(px, py, 0.5, 0.28, 0.5, 0.34, 0.04),
        ellipse,
        capsule(px, py, 0.4, 0.38, 0.16, 0.58, 0.035),
        capsule(px, py, 0.6, 0.38, 0.82, 0.47, 0.035),
        capsule(px, py, 0.82, 0.47, 0.64, 0.6, 0.035),
        capsule(px, py, 0.45, 0.64, 0.36, 0.93, 0.045),
        capsule(px, py, 0.55, 0.64, 0.64, 0.93, 0.045),
        disc(px, py, 0.86, 0.86, 0.06),
      );
      for (const [ex, ey] of [[0.455, 0.18], [0.545, 0.18]]) d = Math.max(d, -disc(px, py, ex, ey, 0.022));
      const alpha = Math.min(1, Math.max(0, 0.5 - d * s));
      rgba.set([120, 110, 100, Math.round(alpha * 255)], (y * w + x) * 4);
    }
  return rgba;
}
