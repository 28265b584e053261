"""``planar app``: an interactive simulator in the browser, served on 127.0.0.1 with Bokeh (the
``app`` extra). :mod:`planar.app.forms` reads and checks the typed dimensions,
:mod:`planar.app.frames` solves the circuit and lays it out, :mod:`planar.app.page` is the page
and its server; only the page imports Bokeh.
"""
