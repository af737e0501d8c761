"""How long a results database locked by another writer is waited for: 30 s, whether the
store writes (a study run) or only reads (show, export, plot).  Read back from SQLite itself
(``PRAGMA busy_timeout``), not from the call that set it."""

from __future__ import annotations

from supcoord.study.store import ResultStore


def test_a_locked_database_is_waited_for_thirty_seconds(tmp_path):
    path = tmp_path / "results.sqlite"
    with ResultStore(path) as writer:
        assert writer.con.execute("PRAGMA busy_timeout").fetchone()[0] == 30_000  # ms
        with ResultStore(path, create=False) as reader:
            assert reader.con.execute("PRAGMA busy_timeout").fetchone()[0] == 30_000
