"""``planar app`` through a real browser: how long the page takes to load, and how many times a
second the drawing is redrawn while the input of a six-bar is dragged.

Headless Debian chromium (``apt-get install chromium``) driven by Playwright's Python API, as
``tests/test_app.py`` drives it. The load is the time from navigation to the first pose drawn (its
readout printed). The drag presses the mouse on the slider's handle and sends mouse moves across
the slider every 8 ms (a 125 Hz mouse) for ``--seconds``, without waiting for each to be handled,
as a hand's mouse would; a requestAnimationFrame loop in the page counts the display frames in
which the pose shown changed: redraws per second. For comparison it also steps the slider one pose
per display frame from the page itself (the same callback, without input events).

    python3 benchmarks/app_speed.py                 # the Watt six-bar, 3 s of dragging
    python3 benchmarks/app_speed.py --seconds 10 --mechanism two_loop_six_bar
"""

import argparse
import asyncio
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from tests.test_app import ARGS, CHROMIUM, running_app  # noqa: E402

COUNT = """() => {
  const r = Bokeh.documents[0].get_model_by_name("planar-readout");
  window.planar_frames = 0;
  let last = r.text;
  const tick = () => { if (r.text !== last) { last = r.text; window.planar_frames++; } requestAnimationFrame(tick); };
  requestAnimationFrame(tick);
}"""

STEP = """async (seconds) => {
  const slider = [...Bokeh.documents[0].all_models].find(m => m.css_classes && m.css_classes.includes("planar-scrub"));
  const N = slider.end + 1;
  let k = 0, frames = 0, busy = 0;
  const t0 = performance.now();
  await new Promise(done => {
    const tick = () => {
      const a = performance.now();
      slider.value = (k = (k + 3) % N);
      busy += performance.now() - a;
      frames++;
      if (performance.now() - t0 < 1000 * seconds) requestAnimationFrame(tick); else done();
    };
    requestAnimationFrame(tick);
  });
  return [frames, (performance.now() - t0) / 1000, busy / frames];
}"""


async def drag(page, seconds, period=0.008):
    """Drag the slider's handle to and fro for ``seconds``, a mouse move every ``period`` s;
    returns (redraws, elapsed s, moves)."""
    handle = await page.locator(".planar-scrub .noUi-handle").bounding_box()
    base = await page.locator(".planar-scrub .noUi-base").bounding_box()
    x0, y = handle["x"] + handle["width"] / 2, handle["y"] + handle["height"] / 2
    cdp = await page.context.new_cdp_session(page)

    def mouse(kind, x, buttons):
        return cdp.send("Input.dispatchMouseEvent", {"type": kind, "x": x, "y": y, "button": "left",
                                                     "buttons": buttons, "clickCount": 1})

    await mouse("mouseMoved", x0, 0)
    await mouse("mousePressed", x0, 1)
    await page.evaluate(COUNT)
    sent, t0 = [], time.perf_counter()
    while (t := time.perf_counter() - t0) < seconds:
        f = (1 - math.cos(2 * math.pi * t / 2.0)) / 2  # across and back every 2 s
        sent.append(asyncio.ensure_future(mouse("mouseMoved", base["x"] + f * base["width"], 1)))
        await asyncio.sleep(period)
    await asyncio.gather(*sent)
    elapsed = time.perf_counter() - t0
    frames = await page.evaluate("() => window.planar_frames")
    await mouse("mouseReleased", base["x"], 0)
    return frames, elapsed, len(sent)


async def run(args):
    from playwright.async_api import async_playwright

    with running_app() as url:
        async with async_playwright() as pw:
            browser = await pw.chromium.launch(executable_path=CHROMIUM, args=ARGS)
            page = await browser.new_page(viewport={"width": 1600, "height": 1000})
            loads = []
            for _ in range(3):
                t0 = time.perf_counter()
                await page.goto(url)
                await page.locator("span.planar-input").wait_for(timeout=30000)
                loads.append(time.perf_counter() - t0)
            print(f"page load to the first pose drawn: best {min(loads):.2f} s, worst {max(loads):.2f} s (3 loads)")
            await page.locator(".planar-choice select").select_option(args.mechanism)
            await asyncio.sleep(2.0)  # the circuit solved and sent
            frames, elapsed, moves = await drag(page, args.seconds)
            print(f"{args.mechanism}: dragging the input with the mouse for {elapsed:.1f} s ({moves} moves): "
                  f"{frames} redraws, {frames / elapsed:.1f} redraws per second")
            frames, elapsed, busy = await page.evaluate(STEP, args.seconds)
            print(f"{args.mechanism}: the slider stepped one pose per display frame by the page for {elapsed:.1f} s: "
                  f"{frames / elapsed:.1f} redraws per second, {busy:.2f} ms of script per pose")
            await browser.close()


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--seconds", type=float, default=3.0)
    p.add_argument("--mechanism", default="watt_six_bar")
    asyncio.run(run(p.parse_args(argv)))


if __name__ == "__main__":
    main()
