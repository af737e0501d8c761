"""The results database's guards: how long a database locked by another writer is waited
for (30 s, whether the store writes, a study run, or only reads: show, export, plot; read
back from SQLite itself, ``PRAGMA busy_timeout``), and never a database written over one of
the run's inputs."""

from __future__ import annotations

import pytest

from supcoord.errors import InputError
from supcoord.study.store import ResultStore


def test_a_locked_database_is_waited_for_thirty_seconds(tmp_path):
    path = tmp_path / "results.sqlite"
    with ResultStore(path) as writer:
        assert writer.con.execute("PRAGMA busy_timeout").fetchone()[0] == 30_000  # ms
        with ResultStore(path, create=False) as reader:
            assert reader.con.execute("PRAGMA busy_timeout").fetchone()[0] == 30_000


def test_the_database_is_never_written_over_an_input(tmp_path):
    spec = tmp_path / "study.toml"
    spec.write_text("the study's own file\n")
    with pytest.raises(InputError) as info:
        ResultStore(spec, inputs=[tmp_path / "other.toml", spec])
    assert str(info.value).startswith(f"results database: '{spec}' is also an input of this run")
    assert spec.read_text() == "the study's own file\n"
    fresh = tmp_path / "results.sqlite"
    with ResultStore(fresh, inputs=[spec]):  # another file: written
        pass
    assert fresh.stat().st_size > 0
