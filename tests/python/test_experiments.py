"""The ``quatnav experiment NAME`` dispatcher: registration by name, options, exit status."""
import sys
import types

import pytest

from quatnav import cli, experiments


def _fake_module(calls):
    mod = types.ModuleType("quatnav_fake_experiment")

    def add_arguments(parser):
        parser.add_argument("--json")

    def run(args):
        calls.append(args.json)
        return 0

    mod.add_arguments, mod.run = add_arguments, run
    return mod


def test_registered_experiment_is_dispatched(monkeypatch):
    calls = []
    monkeypatch.setitem(sys.modules, "quatnav_fake_experiment", _fake_module(calls))
    monkeypatch.setitem(experiments.EXPERIMENTS, "fake", "quatnav_fake_experiment")
    assert cli.main(["experiment", "fake", "--json", "out.json"]) == 0
    assert calls == ["out.json"]


def test_unknown_experiment():
    with pytest.raises(KeyError, match="unknown experiment"):
        experiments.load("no-such-experiment")
    with pytest.raises(SystemExit):
        cli.main(["experiment", "no-such-experiment"])


def test_every_registered_experiment_has_add_arguments_and_run():
    for name in experiments.EXPERIMENTS:
        mod = experiments.load(name)
        assert callable(mod.add_arguments) and callable(mod.run), name
