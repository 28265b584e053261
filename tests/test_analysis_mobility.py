"""Mobility reports: degrees of freedom, Grubler's count and redundant joints of every builder."""

import pytest

import planar
from planar.analysis import mobility
from planar.mechanisms import CATALOGUE, planetary_gear_train


@pytest.mark.parametrize("name", sorted(CATALOGUE))
def test_every_builder_reports_its_mobility(name):
    m = CATALOGUE[name]()
    report = mobility(m)
    assert report.dof == len(report.inputs) == report.coordinates - report.rank
    assert report.grubler == report.coordinates - report.joint_rows
    # each redundant joint row is one more than Grubler counts
    assert report.dof - report.grubler >= 0
    assert mobility(m.compile()) == report == mobility(m.sweep(m.compile().u0[None]))


@pytest.mark.parametrize("planets", [1, 2, 4])
def test_planetary_redundancy(planets):
    report = mobility(planetary_gear_train(planets=planets))
    assert (report.grubler, report.dof, len(report.redundant_joints)) == (2 - planets, 1, planets - 1)
    assert "redundant joints" in str(report)


def test_mobility_refuses_other_things():
    with pytest.raises(planar.ModelError, match="mobility needs"):
        mobility(3)
