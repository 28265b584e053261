"""The app's page: Bokeh widgets and figures over :mod:`planar.app.forms` and
:mod:`planar.app.frames`, served on 127.0.0.1 by :func:`serve`.

Each change of a dimension solves the whole circuit once, in Python; the page then animates,
scrubs and plots in the browser from the stored poses (:mod:`planar.app.scripts`: no round trip
to the server per frame). A single value typed into the query field is solved on its own.

One module over 400 lines because it is one class: the page's widgets and the handlers that
read and write them share its state; the design forms, the solved frames and the browser's
scripts are modules of their own.
"""

import base64
import tempfile
from pathlib import Path

import numpy as np

from planar.app.forms import FORMS, Design, FileDesign
from planar.app.frames import output_label, outputs, pose_lines, solve
from planar.app.scripts import DOWNLOAD, PLAY, SHOW
from planar.draw import ACCELERATION, EDGE, EVENT_MARK, PATH_COLOURS, VELOCITY
from planar.errors import InputError, PlanarError
from planar.results import Status
from planar.units import ANGLE_UNITS, LENGTH_UNITS, RATE_UNITS, Units

SAMPLES = 721  # poses on a circuit: a drag across the slider's 600 pixels lands on a new pose each pixel

FILE = "mechanism file"
FIELD_WIDTH = 160


def _fmt(v):
    return f"{v:.10g}"


def _message(lines, kind):
    colour = {"error": "#b00020", "ok": "#1b5e20", "note": "#444"}[kind]
    body = "<br>".join(lines)
    return f'<div class="planar-message planar-{kind}" style="color:{colour};max-width:330px">{body}</div>'


class Page:
    """One browser tab's document: the widgets, the current design and its solved circuit."""

    def __init__(self, doc, start=None):
        from bokeh.layouts import column, row
        from bokeh.models import (Arrow, Button, CheckboxGroup, ColumnDataSource, CustomJS, Div, FileInput,
                                  LabelSet, Select, Slider, TextInput, Toggle, VeeHead)
        from bokeh.plotting import figure

        self.doc = doc
        self._quiet = False  # True while the page sets its unit selectors itself
        self.design = None
        self.circuit = None
        self.model = None
        self.file = start  # a FileDesign opened with the page (planar app FILE)
        self.TextInput = TextInput
        names = list(FORMS) + ([FILE] if start else [])
        self.choice = Select(title="mechanism", value=FILE if start else "four_bar", options=names, width=200,
                             css_classes=["planar-choice"])
        self.opener = FileInput(accept=".json", title="open a mechanism file", width=200, css_classes=["planar-open"])
        self.length = Select(title="length", value="cm", options=list(LENGTH_UNITS), width=70)
        self.angle = Select(title="angle", value="deg", options=list(ANGLE_UNITS), width=70)
        self.rate_unit = Select(title="rate unit", value="rad/s", options=list(RATE_UNITS), width=80)
        self.rate = TextInput(title="input rate [rad/s]", value="10", value_input="10", width=100,
                              css_classes=["planar-field-rate"])
        self.modes = CheckboxGroup(labels=["crossed (other assembly mode)", "second loop crossed"], active=[])
        self.fields = column()
        self.field_widgets = []
        self.checks = Div(text="", width=330)
        self.message = Div(text="", width=330)

        self.frames = ColumnDataSource(dict(x=[], y=[]))
        self.track = ColumnDataSource(dict(x=[], px=[], time=[], out=[], status=[], input_name=[], out_name=[], P=[]))
        self.bars, self.plates, self.wheels, self.guides = (ColumnDataSource(dict(idx=[], xs=[], ys=[], colour=[]))
                                                            for _ in range(4))
        self.pins, self.grounds, self.blocks, self.labels, self.centres = (
            ColumnDataSource(dict(idx=[], x=[], y=[], name=[])) for _ in range(5))
        self.vel, self.acc = (ColumnDataSource(dict(i0=[], i1=[], x0=[], y0=[], x1=[], y1=[])) for _ in range(2))
        self.paths = ColumnDataSource(dict(xs=[], ys=[], colour=[], name=[]))
        self.marks = ColumnDataSource(dict(x=[], y=[], colour=[], kind=[]))
        self.plot_marks = ColumnDataSource(dict(x=[], y=[], colour=[], kind=[]))
        self.marker = ColumnDataSource(dict(x=[], y=[]))
        self.download = ColumnDataSource(dict(name=[], content=[], mime=[]))

        tools = "pan,wheel_zoom,box_zoom,reset,save"
        self.view = figure(width=640, height=520, match_aspect=True, tools=tools, title="mechanism",
                           output_backend="canvas")
        v = self.view
        paths = v.multi_line("xs", "ys", source=self.paths, line_color="colour", line_dash="dashed", line_width=1.5)
        v.multi_line("xs", "ys", source=self.guides, line_color=EDGE, line_width=2)
        v.patches("xs", "ys", source=self.wheels, fill_alpha=0.0, line_color=EDGE, line_width=1.5)
        v.patches("xs", "ys", source=self.plates, fill_color="colour", fill_alpha=0.85, line_color=EDGE, line_width=1.5)
        v.multi_line("xs", "ys", source=self.bars, line_color=EDGE, line_width=10, line_cap="round")
        v.multi_line("xs", "ys", source=self.bars, line_color="colour", line_width=7, line_cap="round")
        v.scatter("x", "y", source=self.blocks, marker="square", size=22, fill_color="#fdbf6f", line_color=EDGE)
        v.scatter("x", "y", source=self.grounds, marker="triangle", size=16, fill_color="#bbbbbb", line_color=EDGE)
        v.scatter("x", "y", source=self.pins, size=8, fill_color="white", line_color=EDGE, line_width=1.5)
        self.bounds = ColumnDataSource(dict(x=[], y=[]))  # the box every pose fits in: the view's extent
        box = v.scatter("x", "y", source=self.bounds, alpha=0.0)
        v.x_range.renderers = v.y_range.renderers = [box]
        marks = v.scatter("x", "y", source=self.marks, marker="square", size=10, fill_color="colour", line_color="white")
        centres = v.scatter("x", "y", source=self.centres, marker="x", size=10, line_color="#9467bd", line_width=2,
                            visible=False)
        centre_names = LabelSet(x="x", y="y", text="name", source=self.centres, x_offset=5, y_offset=-14,
                                text_font_size="10px", text_color="#9467bd", visible=False)
        head = dict(size=8)
        vel = Arrow(end=VeeHead(fill_color=VELOCITY, line_color=VELOCITY, **head), source=self.vel, x_start="x0",
                    y_start="y0", x_end="x1", y_end="y1", line_color=VELOCITY, line_width=2)
        acc = Arrow(end=VeeHead(fill_color=ACCELERATION, line_color=ACCELERATION, **head), source=self.acc,
                    x_start="x0", y_start="y0", x_end="x1", y_end="y1", line_color=ACCELERATION, line_width=2,
                    visible=False)
        labels = LabelSet(x="x", y="y", text="name", source=self.labels, x_offset=6, y_offset=6, text_font_size="11px",
                          text_font_style="italic")
        for a in (vel, acc, labels, centre_names):
            v.add_layout(a)
        self.layers = {"paths": [paths], "velocity": [vel], "acceleration": [acc], "labels": [labels],
                       "limits and branch events": [marks], "instant centres": [centres, centre_names]}
        self.show_layers = CheckboxGroup(labels=list(self.layers), active=[0, 1, 3, 4], inline=True)
        self.show_layers.js_on_change("active", CustomJS(args=dict(groups=list(self.layers.values()), box=self.show_layers),
                                                         code="groups.forEach((g, k) => g.forEach(r => r.visible = box.active.includes(k)));"))

        self.slider = Slider(start=0, end=1, value=0, step=1, title="pose along the circuit (drag to move the input)",
                             width=640, show_value=False, css_classes=["planar-scrub"])
        self.play = Toggle(label="Play / pause", active=False, width=120, css_classes=["planar-play"])
        self.speed = Slider(start=0.05, end=4, value=1.0, step=0.05, title="speed (x real time)", width=240)
        self.readout = Div(text="", width=640, css_classes=["planar-readout"], name="planar-readout")
        # the pose shown is the page's business: no message to the server per frame
        self.slider.syncable = self.readout.syncable = False
        show = CustomJS(args=dict(track=self.track, frames=self.frames, slider=self.slider, readout=self.readout,
                                  marker=self.marker, lines=[self.bars, self.plates, self.wheels, self.guides],
                                  dots=[self.pins, self.grounds, self.blocks, self.labels, self.centres],
                                  arrows=[self.vel, self.acc]),
                        code=SHOW)
        self.slider.js_on_change("value", show)
        self.frames.js_on_change("data", show)  # a new circuit: draw its pose at the slider
        self.track.js_on_change("data", show)  # another output plotted
        doc.js_on_event("document_ready", show)
        self.play.js_on_change("active", CustomJS(args=dict(play=self.play, slider=self.slider, speed=self.speed,
                                                            track=self.track), code=PLAY))
        self.download.js_on_change("data", CustomJS(args=dict(download=self.download), code=DOWNLOAD))

        self.output = Select(title="plot", options=[], width=220)
        self.axis = Select(title="against", value="input", options=["input", "time"], width=90)
        self.plot = figure(width=460, height=330, tools="pan,wheel_zoom,box_zoom,reset,save", title="")
        self.plot.line("px", "out", source=self.track, line_width=2, color=PATH_COLOURS[0])
        self.plot.scatter("x", "y", source=self.plot_marks, marker="square", size=9, fill_color="colour",
                          line_color="white")
        self.plot.scatter("x", "y", source=self.marker, size=11, fill_color="#d62728", line_color="white")
        self.query = TextInput(title="solve one input value exactly", placeholder="e.g. 60", width=200,
                               css_classes=["planar-query"])
        self.answer = Div(text="", width=460, css_classes=["planar-answer"])
        buttons = [Button(label=label, width=110, css_classes=[f"planar-export-{kind}"])
                   for label, kind in (("CSV table", "csv"), ("mechanism file", "json"), ("GIF", "gif"))]
        for b, kind in zip(buttons, ("csv", "json", "gif")):
            b.on_click(lambda event, kind=kind: self.export(kind))

        left = column(Div(text="<h2 style='margin:0'>planar</h2>"), row(self.choice), self.opener,
                      row(self.length, self.angle, self.rate_unit), self.rate, self.fields, self.modes, self.checks,
                      self.message, width=350)
        middle = column(self.view, self.slider, row(self.play, self.speed), self.readout, self.show_layers)
        right = column(row(self.output, self.axis), self.plot, row(self.query), self.answer,
                       Div(text="export (PNG: the save tool of each figure)"), row(*buttons))
        doc.add_root(row(left, middle, right))
        doc.add_root(self.download)  # drawn by no figure: a root of its own, so that its changes reach the page
        doc.title = "planar app"

        self.choice.on_change("value", self._guard(lambda a, o, n: self.pick()))
        # the page sends the file's content before its name: read both on the next tick
        self.opener.on_change("value", lambda a, o, n: doc.add_next_tick_callback(lambda: self._shown(self.open_file)))
        self.length.on_change("value", self._guard(lambda a, o, n: self.restate(o, n)))
        self.angle.on_change("value", self._guard(lambda a, o, n: self.reangle(o, n)))
        self.rate_unit.on_change("value", self._guard(lambda a, o, n: self.rerate(o, n)))
        self.rate.on_change("value_input", self._guard(lambda a, o, n: self.refresh()))
        self.modes.on_change("active", self._guard(lambda a, o, n: self.refresh()))
        self.output.on_change("value", self._guard(lambda a, o, n: self.replot()))
        self.axis.on_change("value", self._guard(lambda a, o, n: self.replot()))
        self.query.on_change("value", self._guard(lambda a, o, n: self.ask()))
        if start is not None:
            self.set_units(start.units)
        self.pick()

    def _guard(self, f):
        """The change callback ``f(attr, old, new)`` with its PlanarError shown as the page's message:
        a value the page did not offer (another mechanism, output or unit) may still come from a client."""
        def run(attr, old, new):
            self._shown(f, attr, old, new)
        return run

    def _shown(self, f, *args):
        try:
            f(*args)
        except PlanarError as e:
            self.message.text = _message([str(e)], "error")

    # ---- the design ------------------------------------------------------------------------

    def units(self):
        return Units(self.length.value, self.angle.value, self.rate_unit.value)

    def set_units(self, units):
        self._quiet = True
        self.length.value = units.length if units.length in LENGTH_UNITS else "cm"
        self.angle.value, self.rate_unit.value = units.angle, units.rate
        self._quiet = False

    def show_fields(self, fields, values):
        """One text field per number, titled with its unit (the widget's name is the field's)."""
        widgets = []
        for f in fields:
            text = _fmt(values[f.name])
            unit = self.angle.value if f.kind == "angle" else self.length.value
            w = self.TextInput(title=f"{f.name} [{unit}]", name=f.name, value=text, value_input=text, width=FIELD_WIDTH,
                               css_classes=[f"planar-field-{f.name.replace(' ', '-')}"])
            w.on_change("value_input", self._guard(lambda a, o, n: self.refresh()))
            widgets.append(w)
        from bokeh.layouts import row

        self.field_widgets = widgets
        self.fields.children = [row(*widgets[k:k + 2]) for k in range(0, len(widgets), 2)]  # two a row

    def texts(self):
        return {w.name: w.value_input for w in self.field_widgets}

    def pick(self):
        """A catalogue mechanism (at its default dimensions) or the opened file."""
        if self.choice.value == FILE and self.file is None:
            raise InputError("no mechanism file is open: open one with the file button first")
        if self.choice.value != FILE and self.choice.value not in FORMS:
            raise InputError(f"unknown mechanism {self.choice.value!r}: choose one of {', '.join(FORMS)}")
        if self.choice.value == FILE:
            self.design = self.file
            self.show_fields(self.file.fields, {f.name: f.default for f in self.file.fields})
        else:
            form = FORMS[self.choice.value]
            self.design = Design(form, {f.name: f.default for f in form.fields}, self.units())
            self.show_fields(form.fields, self.design.values)
        self.modes.visible = self.choice.value != FILE
        two = self.choice.value not in (FILE, "four_bar", "slider_crank")
        self.modes.labels = ["crossed (other assembly mode)"] + (["second loop crossed"] if two else [])
        self.refresh()

    def open_file(self):
        from bokeh.core.property.descriptors import UnsetValueError

        try:
            name = self.opener.filename or "mechanism.json"
        except UnsetValueError:  # (a client that sent the content alone)
            name = "mechanism.json"
        try:
            text = base64.b64decode(self.opener.value, validate=True).decode("utf-8")
        except (ValueError, UnicodeDecodeError):  # (binascii.Error, a ValueError: not base64 at all)
            self.message.text = _message([f"{name}: not a text file (a mechanism file is UTF-8 JSON)"], "error")
            return
        self.open_text(text, name)

    def open_text(self, text, name):
        """Open the mechanism file ``text`` (named ``name``) in its own units."""
        from planar.io import loads

        try:
            mf = loads(text, name)
        except PlanarError as e:
            self.message.text = _message([str(e)], "error")
            return
        self.file = FileDesign(mf.data, name)
        self.set_units(mf.units)
        if FILE not in self.choice.options:
            self.choice.options = self.choice.options + [FILE]
        if self.choice.value == FILE:
            self.pick()
        else:
            self.choice.value = FILE

    def restate(self, old, new):
        """Lengths restated in the new unit: the same mechanism, other numbers."""
        if self._quiet or self.design is None:
            return
        try:
            self.design = self.current(Units(old, self.angle.value, self.rate_unit.value)).restated(new)
        except PlanarError as e:
            self.message.text = _message([str(e)], "error")
            return
        if isinstance(self.design, FileDesign):
            self.file = self.design
            self.show_fields(self.design.fields, {f.name: f.default for f in self.design.fields})
        else:
            self.show_fields(self.design.form.fields, self.design.values)
        self.refresh()

    def reangle(self, old, new):
        if self._quiet:
            return
        for w in self.field_widgets:
            if w.name == "start":
                text = self._convert(w.value_input, Units(angle=old).angle_to_internal, Units(angle=new).angle_from_internal)
                w.update(value=text, value_input=text, title=f"start [{new}]")
        self.refresh()

    def rerate(self, old, new):
        if self._quiet:
            return
        text = self._convert(self.rate.value_input, Units(rate=old).rate_to_internal, Units(rate=new).rate_from_internal)
        self.rate.value = self.rate.value_input = text

    @staticmethod
    def _convert(text, to_internal, from_internal):
        """A number typed in one unit, in another (as typed where it is no number, or overflows:
        the field's check says so)."""
        try:
            with np.errstate(over="ignore"):
                v = float(from_internal(to_internal(float(text))))
        except ValueError:
            return text
        return _fmt(v) if np.isfinite(v) else text

    def current(self, units=None):
        """The design as typed now (raises the field's InputError)."""
        units = units or self.units()
        if isinstance(self.design, FileDesign):
            return self.design.with_values(self.design.read(self.texts()))
        return Design(self.design.form, self.design.form.read(self.texts(), units.length), units,
                      0 in self.modes.active, 1 in self.modes.active)

    def refresh(self):
        """Read every field, check, build, solve the circuit and send it to the page."""
        units = self.units()
        try:
            design = self.current(units)
            self.checks.text = _message(design.checks(), "note")
            rate = _rate(self.rate.value_input, units)
            model = design.build().compile()
            model.require_driver()  # (a file of no input: nothing to sweep)
            self.rate.title = f"input rate [{units.input_label(bool(model.input_lengths[0]), 1)}]"
            checks = design.checks() + _loop_checks(design, model)
            self.checks.text = _message(checks, "note")
            circuit = solve(model, units, rate, SAMPLES)
        except PlanarError as e:
            self.message.text = _message([str(e)], "error")
            return
        self.model, self.circuit = model, circuit
        ok = int(np.count_nonzero(circuit.res.ok))
        self.message.text = _message([f"{model.name} assembles: {len(circuit.x)} poses on its circuit, {ok} with valid "
                                      f"rates"]
                                     + circuit.event_lines(), "ok")
        self.send()

    # ---- the page's data -------------------------------------------------------------------

    def send(self):
        c = self.circuit
        specs = outputs(c.model)
        labels = [(s, output_label(s, c.units, c.model)) for s in specs]
        keep = self.output.value if self.output.value in specs else next(
            (s for s in specs if s.startswith(("angle:rocker", "travel:", "angle:link6", "angle:rocker2"))), specs[0])
        self.output.options = labels
        self.output.value = keep
        self.play.tags = [1 if c.rate >= 0 else -1]

        def idx_rows(groups, colours=None):
            return dict(idx=groups, xs=[[] for _ in groups], ys=[[] for _ in groups],
                        colour=colours or [EDGE] * len(groups))

        bars = [k for k, b in enumerate(c.bodies) if len(b) == 2]
        plates = [k for k, b in enumerate(c.bodies) if len(b) > 2]
        self.bars.data = idx_rows([c.bodies[k] for k in bars], [c.colours[k] for k in bars])
        self.plates.data = idx_rows([c.bodies[k] for k in plates], [c.colours[k] for k in plates])
        self.wheels.data = idx_rows(c.wheels)
        self.guides.data = idx_rows(c.guides)
        for src, idx, names in ((self.pins, c.pins, None), (self.grounds, c.grounds, None), (self.blocks, c.blocks, None),
                                (self.labels, c.points, c.labels),
                                (self.centres, [i for _, i in c.centres], [n for n, _ in c.centres])):
            src.data = dict(idx=idx, x=[np.nan] * len(idx), y=[np.nan] * len(idx), name=names or [""] * len(idx))
        for src, k in ((self.vel, 2), (self.acc, 3)):
            i0, i1 = [a[1] for a in c.arrows], [a[k] for a in c.arrows]
            src.data = dict(i0=i0, i1=i1, x0=[np.nan] * len(i0), y0=[np.nan] * len(i0), x1=[np.nan] * len(i0),
                            y1=[np.nan] * len(i0))
        self.paths.data = dict(xs=[p[:, 0] for p in c.paths.values()], ys=[p[:, 1] for p in c.paths.values()],
                               colour=[PATH_COLOURS[k % len(PATH_COLOURS)] for k in range(len(c.paths))],
                               name=list(c.paths))
        marks = [(EVENT_MARK[kind][1], kind, p) for kind, _, _, pts in c.event_marks() for p in pts]
        self.marks.data = dict(x=[p[0] for *_, p in marks], y=[p[1] for *_, p in marks],
                               colour=[m[0] for m in marks], kind=[m[1] for m in marks])
        drawn = [i for group in (c.bodies + c.wheels + c.guides) for i in group] + c.pins + c.grounds + c.blocks
        px = np.concatenate([c.X[:, drawn].ravel()] + [p[:, 0] for p in c.paths.values()])
        py = np.concatenate([c.Y[:, drawn].ravel()] + [p[:, 1] for p in c.paths.values()])
        lo, hi = np.array([np.nanmin(px), np.nanmin(py)]), np.array([np.nanmax(px), np.nanmax(py)])
        pad = 0.08 * max(hi - lo) + 1e-9
        self.bounds.data = dict(x=[lo[0] - pad, hi[0] + pad], y=[lo[1] - pad, hi[1] + pad])
        L = c.units.length or "length unit"
        self.view.title.text = (f"{c.model.name}: {len(c.x)} poses, solved once; arrows: 1 {L} = "
                                f"{1 / c.scales[0]:.3g} {c.units.label('speed')}, {1 / c.scales[1]:.3g} "
                                f"{c.units.label('accel')}")
        self.slider.end = len(c.x) - 1  # the page keeps its pose index (clamped when it draws)
        self.replot(send_frames=True)

    def replot(self, send_frames=False):
        c = self.circuit
        if c is None:
            return
        spec = self.output.value
        if spec not in outputs(c.model):
            raise InputError(f"unknown output {spec!r}: choose one of the list")
        label = output_label(spec, c.units, c.model)
        y = c.series(spec)
        px = c.x if self.axis.value == "input" else c.time
        status = [Status(int(s)).name for s in c.res.status]
        name = c.input_label() if self.axis.value == "input" else "time [s]"
        self.track.data = dict(x=c.x, px=px, time=c.time, out=y, status=status, input_name=[c.input_label()] * len(y),
                               out_name=[label] * len(y), P=[c.X.shape[1]] * len(y))
        marks = [(px[i], y[i], EVENT_MARK[kind][1], kind) for kind, i, _, _ in c.event_marks()]
        self.plot_marks.data = dict(x=[m[0] for m in marks], y=[m[1] for m in marks], colour=[m[2] for m in marks],
                                    kind=[m[3] for m in marks])
        self.plot.title.text = label
        self.plot.xaxis.axis_label = name
        self.plot.yaxis.axis_label = label
        if send_frames:  # after the track: the page draws once both are of this circuit
            self.frames.data = dict(x=c.X.ravel(), y=c.Y.ravel())

    # ---- one value, exports ----------------------------------------------------------------

    def ask(self):
        if self.model is None or not self.query.value.strip():
            return
        units = self.units()
        try:
            value = float(self.query.value)
            lines = pose_lines(self.model, units, value, _rate(self.rate.value_input, units))
        except ValueError:
            lines = [f"{self.query.value.strip()!r} is not a number: type an input value like 60"]
        except PlanarError as e:
            lines = [str(e)]
        self.answer.text = "<pre class='planar-pose'>" + "\n".join(lines) + "</pre>"

    def export(self, kind):
        from planar import io
        from planar.app.frames import csv_text
        from planar.cli import default_sweep

        if self.circuit is None:
            return
        c, name = self.circuit, self.circuit.model.name
        try:
            if kind == "csv":
                data, mime = csv_text(c.res, c.units).encode(), "text/csv"
            elif kind == "json":
                design = self.current()
                if isinstance(design, FileDesign):
                    text = io.dumps(io.from_dict(design.data, design.source))
                else:
                    mech = design.build()
                    text = io.dumps(mech, c.units, default_sweep(mech.compile(), c.units))
                data, mime = text.encode(), "application/json"
            else:
                from planar.animate import animate

                with tempfile.TemporaryDirectory() as tmp:
                    path = animate(c.res, Path(tmp) / f"{name}.gif", fps=20, max_frames=60, dpi=72)
                    data, mime = path.read_bytes(), "image/gif"
        except PlanarError as e:
            self.message.text = _message([str(e)], "error")
            return
        self.download.data = dict(name=[f"{name}.{kind}"], content=[base64.b64encode(data).decode()], mime=[mime])


def _rate(text, units):
    """The input rate typed (a number in the page's rate unit), refused by name when not a
    finite, non-zero number."""
    from planar.app.forms import Field, read_number

    v = read_number(text, Field("input rate", "rate", 1.0, "signed"))
    if v == 0:
        raise InputError(f"input rate: 0 {units.rate} does not move the mechanism: type a non-zero rate like 10")
    if not 1e-100 <= abs(v) <= 1e100:  # (the circuit's time axis, the input over the rate, would overflow)
        raise InputError(f"input rate: {v:g} {units.rate} is beyond what the page times (1e-100 to 1e100): type a "
                         f"rate like 10")
    return v


def _loop_checks(design, model):
    """The Grashof class of a file's mechanism that is one loop of four revolutes."""
    if not isinstance(design, FileDesign):
        return []
    from planar.app.forms import grashof_line
    from planar.analysis import four_bar_links

    found = four_bar_links(model)
    return [grashof_line(found[0], found[1] or "crank")] if found else []


def serve(port=5006, open_browser=True, start=None):
    """Serve the app on 127.0.0.1:``port`` until interrupted (Ctrl-C); ``start`` is a
    :class:`planar.app.forms.FileDesign` to open with each page."""
    import logging
    import signal

    from bokeh.server.server import Server

    logging.basicConfig(level=logging.WARNING)  # a failing callback is reported in the terminal
    server = Server({"/": lambda doc: Page(doc, start)}, port=port, address="127.0.0.1",
                    allow_websocket_origin=[f"127.0.0.1:{port}", f"localhost:{port}"])
    server.start()
    try:
        # Ctrl-C stops the loop from inside it, whatever the loop is doing when it comes (where
        # the event loop takes no signal handlers, as on Windows, it interrupts the loop instead)
        server.io_loop.asyncio_loop.add_signal_handler(signal.SIGINT, server.io_loop.stop)
    except NotImplementedError:
        pass
    print(f"planar app: http://127.0.0.1:{port}/ (Ctrl-C to stop)", flush=True)
    if open_browser:
        server.io_loop.add_callback(server.show, "/")
    try:
        server.io_loop.start()
    except KeyboardInterrupt:
        pass
    finally:
        server.stop()
    return 0
