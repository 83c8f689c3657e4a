// agreement.mjs: how far one frame's light is from another's (RGBA float arrays
// from render.mjs's tasks), over the pixels `ref` covers (alpha set): their
// channel count, `ref`'s summed light, the mean of `other` over `ref`'s, and
// the RMSE relative to `ref`'s mean.
export function agreement(ref, other) {
  let n = 0, sr = 0, so = 0, se = 0;
  for (let i = 0; i < ref.length; i += 4) {
    if (!ref[i + 3]) continue;
    for (let k = 0; k < 3; k++) {
      sr += ref[i + k];
      so += other[i + k];
      se += (other[i + k] - ref[i + k]) ** 2;
      n++;
    }
  }
  return { channels: n, light: sr, mean: so / sr, rmse: Math.sqrt(se / n) / (sr / n) };
}
