"""The sweep store (roughlight.study.sweep_store): a sweep is measured once for the same settings and code."""
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from roughlight.study import sweep_store

SETTINGS = {"incidence": 30.0, "lighting": {"light": 127.0}, "method": "fast", "render": {"pixels_per_period": 28}}


def fake_measure(calls):
    """A stand-in for run_sweep that writes a small table and records what it measured."""

    def measure(path, surface):
        calls.append(surface["aspect"])
        pq.write_table(pa.table({"aspect": [surface["aspect"]], "call": [len(calls)]}), path)

    return measure


def surfaces(*aspects):
    return [{"kind": "pyramids", "truncation": 0.5, "aspect": a} for a in aspects]


def test_a_sweep_is_measured_once_and_then_taken_from_the_store(tmp_path):
    store, calls = tmp_path / "store", []
    first = [tmp_path / "run1" / f"a{a}.parquet" for a in (0.5, 1.0)]
    (tmp_path / "run1").mkdir()
    done = sweep_store.measure_sweeps(first, surfaces(0.5, 1.0), SETTINGS, fake_measure(calls), store=store)
    assert calls == [0.5, 1.0] and done["reused"] == []
    # the same sweeps again (the job rerun for a new aspect) and one new one: only the new one is measured
    (tmp_path / "run2").mkdir()
    second = [tmp_path / "run2" / f"a{a}.parquet" for a in (0.5, 0.7, 1.0)]
    messages = []
    done = sweep_store.measure_sweeps(second, surfaces(0.5, 0.7, 1.0), SETTINGS, fake_measure(calls), store=store,
                                      log=messages.append)
    assert calls == [0.5, 1.0, 0.7]
    assert done["measured"] == [str(second[1])] and done["reused"] == [str(second[0]), str(second[2])]
    assert messages[-1] == "1 sweeps measured, 2 taken from the store"
    for old, new in ((first[0], second[0]), (first[1], second[2])):
        assert old.read_bytes() == new.read_bytes()


def test_a_changed_setting_or_code_measures_anew(tmp_path, monkeypatch):
    store, calls = tmp_path / "store", []
    path = [tmp_path / "a.parquet"]
    sweep_store.measure_sweeps(path, surfaces(1.0), SETTINGS, fake_measure(calls), store=store)
    sweep_store.measure_sweeps(path, surfaces(1.0), {**SETTINGS, "lighting": {"light": 255.0}}, fake_measure(calls),
                               store=store)
    assert calls == [1.0, 1.0]
    # the same settings under other code (another package source or library version): measured again
    monkeypatch.setattr(sweep_store, "code_digest", lambda: "other code")
    sweep_store.measure_sweeps(path, surfaces(1.0), SETTINGS, fake_measure(calls), store=store)
    assert calls == [1.0, 1.0, 1.0]
    # and without a store every sweep is measured
    sweep_store.measure_sweeps(path, surfaces(1.0), SETTINGS, fake_measure(calls), store=None)
    assert len(calls) == 4


def test_a_sweep_drawn_by_another_renderer_is_never_handed_back(tmp_path, monkeypatch):
    """The key names the GL renderer and driver the job draws on (as the GL reports them): a run on a GPU
    (render.platform egl) never takes llvmpipe's sweeps. Unchanged, the same renderer reuses its own."""
    from roughlight.render import methods

    store, calls = tmp_path / "store", []
    path = [tmp_path / "a.parquet"]
    here = methods.renderer_identity("fast")
    assert "OpenGL" in here and methods.renderer_identity("reference") == methods.NO_OPENGL
    sweep_store.measure_sweeps(path, surfaces(1.0), SETTINGS, fake_measure(calls), store=store)
    sweep_store.measure_sweeps(path, surfaces(1.0), SETTINGS, fake_measure(calls), store=store)
    assert calls == [1.0]
    monkeypatch.setattr(methods, "renderer_identity", lambda name: "NVIDIA RTX, OpenGL 4.6 NVIDIA 550.1, egl")
    sweep_store.measure_sweeps(path, surfaces(1.0), SETTINGS, fake_measure(calls), store=store)
    assert calls == [1.0, 1.0]


def test_a_failed_sweep_leaves_nothing_in_the_store(tmp_path):
    def failing(path, surface):
        raise RuntimeError("no OpenGL")

    with pytest.raises(RuntimeError):
        sweep_store.measure_sweeps([tmp_path / "a.parquet"], surfaces(1.0), SETTINGS, failing, store=tmp_path / "s")
    assert not (tmp_path / "s").exists() or not any((tmp_path / "s").rglob("*.parquet"))


def test_every_library_of_the_key_is_installed():
    """A distribution name that pip does not know would leave its version out of every key unnoticed."""
    from importlib import metadata

    assert all(metadata.version(name) for name in sweep_store.LIBRARIES)


def test_keys_follow_settings_not_their_order():
    a = sweep_store.sweep_key({"x": 1, "y": {"p": 2, "q": 3}})
    assert a == sweep_store.sweep_key({"y": {"q": 3, "p": 2}, "x": 1})
    assert a != sweep_store.sweep_key({"x": 1, "y": {"p": 2, "q": 4}})
    assert len(sweep_store.code_digest()) == 64


def test_files_and_surfaces_must_pair_up(tmp_path):
    with pytest.raises(ValueError, match="2 output files for 1 surfaces"):
        sweep_store.measure_sweeps(["a", "b"], surfaces(1.0), SETTINGS, fake_measure([]), store=tmp_path)


def test_a_sweep_stored_in_an_earlier_format_is_never_handed_back(tmp_path, monkeypatch):
    """The key holds the sweep files' format (roughlight.study.tables.SWEEP_FORMAT): a sweep stored before the
    means before rounding and without shadows were columns is measured anew, though settings and code agree."""
    from roughlight.study import tables

    store, calls = tmp_path / "store", []
    path = [tmp_path / "a.parquet"]
    monkeypatch.setattr(sweep_store, "code_digest", lambda: "the same code")
    monkeypatch.setattr(tables, "SWEEP_FORMAT", 1)
    sweep_store.measure_sweeps(path, surfaces(1.0), SETTINGS, fake_measure(calls), store=store)
    monkeypatch.setattr(tables, "SWEEP_FORMAT", 2)
    sweep_store.measure_sweeps(path, surfaces(1.0), SETTINGS, fake_measure(calls), store=store)
    sweep_store.measure_sweeps(path, surfaces(1.0), SETTINGS, fake_measure(calls), store=store)
    assert calls == [1.0, 1.0]
