"""Fuzzing mechanism files: any mutation of a valid file either loads (and then compiles or is
refused with a PlanarError) or is refused with a FileFormatError; nothing else escapes.
"""

import json

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import planar
import planar.io
from planar.errors import FileFormatError
from planar.mechanisms import CATALOGUE

TEXTS = {name: planar.io.dumps(build()) for name, build in CATALOGUE.items()}
json_values = st.recursive(
    st.none() | st.booleans() | st.floats(allow_nan=True) | st.integers() | st.text(max_size=5),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=5), inner, max_size=3),
    max_leaves=6,
)


def paths(doc, prefix=()):
    """Every path to a value inside a JSON document."""
    yield prefix
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield from paths(v, prefix + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield from paths(v, prefix + (i,))


def must_be_handled(text):
    try:
        doc = planar.io.loads(text)
    except FileFormatError as e:
        assert str(e), "an error must say what is wrong"
        return "refused"
    try:
        doc.mechanism.compile()
    except planar.PlanarError:
        return "refused at compile"
    return "loaded"


@given(name=st.sampled_from(sorted(TEXTS)), data=st.data())
def test_replaced_or_deleted_fields(name, data):
    doc = json.loads(TEXTS[name])
    where = data.draw(st.sampled_from([p for p in paths(doc) if p]))
    parent = doc
    for k in where[:-1]:
        parent = parent[k]
    if data.draw(st.booleans()):
        del parent[where[-1]]
    else:
        parent[where[-1]] = data.draw(json_values)
    must_be_handled(json.dumps(doc))


@given(name=st.sampled_from(sorted(TEXTS)), cut=st.floats(0, 1))
def test_truncated_files(name, cut):
    text = TEXTS[name].rstrip()  # any cut now loses at least the closing brace
    assert must_be_handled(text[: int(cut * (len(text) - 1))]) == "refused"


@given(name=st.sampled_from(sorted(TEXTS)), data=st.data())
def test_corrupted_characters(name, data):
    text = list(TEXTS[name])
    for _ in range(data.draw(st.integers(1, 4))):
        i = data.draw(st.integers(0, len(text) - 1))
        text[i] = data.draw(st.characters(codec="utf-8"))
    must_be_handled("".join(text))


@pytest.mark.parametrize("name", sorted(TEXTS))
def test_every_catalogue_file_round_trips(name):
    doc = planar.io.loads(TEXTS[name])
    assert planar.io.dumps(doc) == TEXTS[name]
    assert np.isfinite(doc.mechanism.compile().q0).all()
