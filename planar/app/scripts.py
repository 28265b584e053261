"""The page's scripts that run in the browser (Bokeh ``CustomJS`` code): a frame drawn from the
stored poses, the play loop and the file download; the server sends data, never a frame."""

# One frame in the browser: every drawn source takes its coordinates from the stored poses by
# the indices the server gave it; the readout and the plot's marker follow.
SHOW = """
const N = track.data.x.length;
const X = frames.data.x, Y = frames.data.y;
if (N == 0 || X.length != N * track.data.P[0]) return;  // the poses and the track of one circuit only
const P = track.data.P[0];
const i = Math.max(0, Math.min(N - 1, Math.round(slider.value)));
const o = i * P;
for (const s of lines) {
  const d = s.data;
  d.xs = Array.from(d.idx, ix => Array.from(ix, k => X[o + k]));
  d.ys = Array.from(d.idx, ix => Array.from(ix, k => Y[o + k]));
  s.change.emit();
}
for (const s of dots) {
  const d = s.data;
  d.x = Array.from(d.idx, k => X[o + k]);
  d.y = Array.from(d.idx, k => Y[o + k]);
  s.change.emit();
}
for (const s of arrows) {
  const d = s.data;
  d.x0 = Array.from(d.i0, k => X[o + k]); d.y0 = Array.from(d.i0, k => Y[o + k]);
  d.x1 = Array.from(d.i1, k => X[o + k]); d.y1 = Array.from(d.i1, k => Y[o + k]);
  s.change.emit();
}
const t = track.data;
marker.data.x = [t.px[i]];
marker.data.y = [t.out[i]];
marker.change.emit();
const fmt = v => (v === null || !isFinite(v)) ? "unsolved" : Number(v).toPrecision(12);
readout.text = `<span class="planar-name">${t.input_name[0]}</span> = <span class="planar-input">${fmt(t.x[i])}</span>` +
  ` &middot; <span class="planar-output-name">${t.out_name[0]}</span> = <span class="planar-output">${fmt(t.out[i])}</span>` +
  ` &middot; t = ${Number(t.time[i]).toFixed(3)} s &middot; <span class="planar-status">${t.status[i]}</span>`;
"""

# Play: advance the time at the input's rate times the speed, and move the slider to the pose
# of that time (the circuit loops).
PLAY = """
if (!play.active) return;
const t = track.data.time, N = t.length;
if (N < 2) return;
const T = t[N - 1];
const dir = play.tags.length ? play.tags[0] : 1;
let state = {i: slider.value, t: t[slider.value], last: performance.now()};
const step = (now) => {
  if (!play.active) return;
  if (slider.value != state.i) state.t = t[slider.value];  // scrubbed meanwhile
  state.t += dir * speed.value * (now - state.last) / 1000;
  state.last = now;
  if (T > 0) state.t = ((state.t % T) + T) % T;
  let lo = 0, hi = N - 1;
  while (hi - lo > 1) { const mid = (lo + hi) >> 1; if (t[mid] <= state.t) lo = mid; else hi = mid; }
  state.i = (state.t - t[lo] < t[hi] - state.t) ? lo : hi;
  if (state.i != slider.value) slider.value = state.i;
  requestAnimationFrame(step);
};
requestAnimationFrame(step);
"""

DOWNLOAD = """
const d = download.data;
if (!d.name.length) return;
const bin = atob(d.content[0]);
const bytes = new Uint8Array(bin.length);
for (let k = 0; k < bin.length; k++) bytes[k] = bin.charCodeAt(k);
const a = document.createElement("a");
a.href = URL.createObjectURL(new Blob([bytes], {type: d.mime[0]}));
a.download = d.name[0];
document.body.appendChild(a);
a.click();
a.remove();
"""
