"""Outputs never lose data: one output function for every writer, checked against hard and
symbolic links, the inputs and the database, a full disk and a read-only file system; a
results database that is not supcoord's, or is corrupt, is refused before any change."""

from __future__ import annotations

import ast
import contextlib
import errno
import io
import json
import os
import sqlite3
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from supcoord.cli.main import main
from supcoord.errors import InputError
from supcoord.outputs import atomic_output, atomic_write_bytes, atomic_write_text, check_output
from supcoord.study.store import APPLICATION_ID, COLUMNS, ResultStore

SRC = Path(__file__).resolve().parents[2] / "src" / "supcoord"


def run(*argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


def one_line(code, err):
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1 and "Traceback" not in err, (code, err)
    return lines[0]


@pytest.fixture
def database(tmp_path):
    """A results database with one case, as ``study run`` leaves it, and its study file."""
    study = tmp_path / "s.toml"
    study.write_text('name = "s"\n[[cases]]\nkind = "paper"\nmodel = "literal"\nsteps = 6\npositioners = [2]\n')
    db = tmp_path / "s.sqlite"
    with ResultStore(db) as store:
        store.record({"key": "k1", "params_key": "p1", "study": "s", "series": "a", "size": 2, "status": "ok",
                      "seconds": 1.5, "extra": {"rank": 3}, "message": "m" * 600})
    return study, db


# --- one function for every writer ----------------------------------------------------------

#: modules allowed to open files for writing themselves, and why
PRIVATE_WRITERS = {
    "outputs.py": "the output function itself",
    "study/child.py": "a case's result, in the case's private temporary folder",
    "study/isolate.py": "a case's task and logs, in its private temporary folder",
}
#: methods that write a file named by their first argument (matplotlib, pandas, pathlib, Pillow)
WRITING_METHODS = {"savefig", "to_csv", "to_parquet", "write_text", "write_bytes", "save"}


def _writes(tree: ast.AST):
    """(line, what) of every file write that does not go to ``atomic_output``'s temporary file."""
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        f = node.func
        first = node.args[0] if node.args else None
        to_tmp = isinstance(first, ast.Name) and first.id in ("tmp", "buf", "f", "fh")
        if isinstance(f, ast.Name) and f.id == "open" and len(node.args) >= 2:
            mode = node.args[1]
            if isinstance(mode, ast.Constant) and isinstance(mode.value, str) and set(mode.value) & set("wax+"):
                if not to_tmp:
                    yield node.lineno, "open(..., " + repr(mode.value) + ")"
        elif isinstance(f, ast.Attribute) and f.attr in WRITING_METHODS and first is not None and not to_tmp:
            yield node.lineno, f.attr
        elif isinstance(f, ast.Attribute) and f.attr == "connect" and isinstance(f.value, ast.Name) \
                and f.value.id == "sqlite3":
            yield node.lineno, "sqlite3.connect"


def test_every_writer_goes_through_the_output_function():
    found = []
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC).as_posix()
        if rel in PRIVATE_WRITERS or rel.startswith("testing/"):
            continue
        for line, what in _writes(ast.parse(path.read_text(encoding="utf-8"))):
            if rel == "study/store.py" and what == "sqlite3.connect":
                continue  # the database, opened after check_output (tested below)
            found.append(f"{rel}:{line}: {what}")
    assert not found, "writes that bypass supcoord.outputs.atomic_output:\n" + "\n".join(found)


def test_the_source_scan_finds_a_direct_write():
    code = "def f(p, fig, frame):\n    fig.savefig(p)\n    frame.to_csv(p)\n    open(p, 'w')\n"
    assert [w for _, w in _writes(ast.parse(code))] == ["savefig", "to_csv", "open(..., 'w')"]


# --- links, inputs, the database ----------------------------------------------------------------


def test_export_through_a_hard_link_to_the_database_is_refused(database, tmp_path):
    study, db = database
    before = db.read_bytes()
    os.link(db, tmp_path / "out.csv")
    line = one_line(*run("study", "export", study, "--out", tmp_path / "out.csv")[::2])
    assert "out.csv" in line and "hard link" in line
    assert db.read_bytes() == before


def test_export_over_the_database_by_another_name_or_a_symlink_is_refused(database, tmp_path):
    study, db = database
    before = db.read_bytes()
    (tmp_path / "sub").mkdir()
    line = one_line(*run("study", "export", study, "--out", tmp_path / "sub" / ".." / "s.sqlite")[::2])
    assert "also an input" in line
    os.symlink(db, tmp_path / "link.csv")
    assert "symbolic link" in one_line(*run("study", "export", study, "--out", tmp_path / "link.csv")[::2])
    assert "also an input" in one_line(*run("study", "export", study, "--format", "csv", "--out", study)[::2])
    assert db.read_bytes() == before


def test_library_export_refuses_the_database_itself(database):
    from supcoord.study.results import export_results

    study, db = database
    before = db.read_bytes()
    with pytest.raises(InputError, match="also an input"):
        export_results(db, db, "csv")
    assert db.read_bytes() == before


def test_output_with_a_hard_link_is_refused_by_every_writer(tmp_path):
    kept = tmp_path / "kept.json"
    kept.write_text("keep me")
    os.link(kept, tmp_path / "plan.json")
    with pytest.raises(InputError, match="hard link"):
        atomic_write_text(tmp_path / "plan.json", "new")
    with pytest.raises(InputError, match="hard link"):
        check_output(tmp_path / "plan.json")
    assert kept.read_text() == "keep me"


def test_output_over_an_input_through_a_hard_link_is_refused(tmp_path):
    source = tmp_path / "in.json"
    source.write_text("input")
    os.link(source, tmp_path / "other.json")
    os.unlink(source)  # only the other name is left: the link count is back to 1, the inode is the input's
    with pytest.raises(InputError, match="also an input"):
        check_output(tmp_path / "other.json", [tmp_path / "other.json"])


def test_solve_output_through_a_hard_link_is_refused(tmp_path):
    problem = tmp_path / "p.json"
    problem.write_text(json.dumps({"layout": {"kind": "points", "xy": [[0, 0], [22.4, 0]]},
                                   "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
                                   "collision": {"buffer": 2.0}, "start": [0, 0], "target": [6, 6]}))
    keep = tmp_path / "keep.json"
    keep.write_text("keep")
    os.link(keep, tmp_path / "plan.json")
    assert "hard link" in one_line(*run("solve", problem, "--out", tmp_path / "plan.json")[::2])
    os.link(problem, tmp_path / "fig.png")
    assert "hard link" in one_line(*run("check", problem, problem, "--figure", tmp_path / "fig.png")[::2])
    assert keep.read_text() == "keep"


def test_study_run_database_through_a_link_or_over_the_study_is_refused(database, tmp_path):
    study, db = database
    before = db.read_bytes()
    os.symlink(db, tmp_path / "link.sqlite")
    assert "symbolic link" in one_line(*run("study", "run", study, "--db", tmp_path / "link.sqlite")[::2])
    line = one_line(*run("study", "run", study, "--db", study)[::2])
    assert "also an input" in line
    assert db.read_bytes() == before


def test_plot_refuses_a_figure_name_that_is_a_hard_link(database, tmp_path):
    study, db = database
    figs = tmp_path / "figs"
    figs.mkdir()
    os.link(db, figs / "time.png")
    before = db.read_bytes()
    assert "hard link" in one_line(*run("study", "plot", db, "--out", figs)[::2])
    assert db.read_bytes() == before and sorted(p.name for p in figs.iterdir()) == ["time.png"]


# --- full disk, read-only file system ----------------------------------------------------------

FULL_DISK = textwrap.dedent("""
    import resource, signal, sys
    from supcoord.errors import InputError
    from supcoord.outputs import atomic_write_bytes
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, (1024, 1024))  # a file may grow to 1 KiB: the disk is 'full'
    try:
        atomic_write_bytes(sys.argv[1], b"x" * 100_000)
    except InputError as exc:
        print(exc)
        sys.exit(2)
""")


def test_full_disk_file_size_limit_leaves_the_old_file_and_names_it(tmp_path):
    out = tmp_path / "plan.json"
    out.write_text("old")
    proc = subprocess.run([sys.executable, "-c", FULL_DISK, str(out)], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2, proc.stderr
    assert str(out) in proc.stdout and "File too large" in proc.stdout
    assert out.read_text() == "old" and sorted(p.name for p in tmp_path.iterdir()) == ["plan.json"]


def _limit_file_size():
    import resource

    resource.setrlimit(resource.RLIMIT_FSIZE, (512, 512))  # `ulimit -f 1`; SIGXFSZ left at its default


def test_study_export_under_ulimit_f_leaves_no_partial_csv(database, tmp_path):
    study, db = database
    out = tmp_path / "out.csv"
    proc = subprocess.run([sys.executable, "-m", "supcoord.cli", "study", "export", str(db), "--out", str(out)],
                          capture_output=True, text=True, timeout=120, preexec_fn=_limit_file_size)
    assert proc.returncode == 2, proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1 and "out.csv" in proc.stderr, proc.stderr
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["s.sqlite", "s.toml"]


def test_no_space_at_fsync_leaves_no_partial_file(tmp_path, monkeypatch):
    """ENOSPC where a file system reports it late (at ``fsync``), simulated by a mock."""
    out = tmp_path / "out.csv"
    out.write_text("old")

    def full(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr("supcoord.outputs.os.fsync", full)
    with pytest.raises(InputError, match="No space left") as info:
        atomic_write_text(out, "new")
    assert str(out) in str(info.value) and out.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]


def test_read_only_file_system_leaves_the_old_file(tmp_path, monkeypatch):
    """A read-only file system, simulated by ``os.replace`` raising ``EROFS`` (the tests run
    as root, which ignores permission bits, and cannot mount a read-only file system)."""
    out = tmp_path / "out.gen"
    out.write_text("old")

    def read_only(src, dst):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS))

    monkeypatch.setattr("supcoord.outputs.os.replace", read_only)
    with pytest.raises(InputError, match="Read-only file system") as info:
        atomic_write_bytes(out, b"new")
    assert "out.gen" in str(info.value) and out.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.gen"]


def test_read_only_folder_refuses_the_temporary_file(tmp_path, monkeypatch):
    """The temporary file cannot be created (``EROFS`` from ``mkstemp``, by a mock): one error, nothing left."""
    out = tmp_path / "fig.png"

    def read_only(*args, **kwargs):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS))

    monkeypatch.setattr("supcoord.outputs.tempfile.mkstemp", read_only)
    with pytest.raises(InputError, match="Read-only") as info:
        with atomic_output(out):
            pytest.fail("the writer must not run")
    assert "fig.png" in str(info.value) and not list(tmp_path.iterdir())


def test_output_under_a_file_or_into_a_fifo_is_refused(tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(InputError, match="does not exist"):
        check_output(tmp_path / "file" / "out.csv")
    os.mkfifo(tmp_path / "fifo")
    with pytest.raises(InputError, match="not a regular file"):
        atomic_write_text(tmp_path / "fifo", "x")
    with pytest.raises(InputError, match="is a directory"):
        atomic_write_text(tmp_path, "x")


# --- the database: someone else's, old, corrupt ----------------------------------------------


def test_a_sqlite_file_of_another_application_is_refused_unchanged(database, tmp_path):
    study, _ = database
    user = tmp_path / "user.sqlite"
    con = sqlite3.connect(user)
    con.execute("CREATE TABLE cases (a, b)")
    con.execute("INSERT INTO cases VALUES (1, 2)")
    con.commit()
    con.close()
    before = user.read_bytes()
    line = one_line(*run("study", "run", study, "--db", user, "--workers", "0")[::2])
    assert "not a supcoord results database" in line and "user.sqlite" in line
    assert user.read_bytes() == before
    for action in ("show", "export"):
        assert "not a supcoord results database" in one_line(*run("study", action, user)[::2])
    assert user.read_bytes() == before and not (tmp_path / "user.csv").exists()


def test_an_old_results_database_without_the_id_is_still_read_and_written(tmp_path):
    old = tmp_path / "old.sqlite"
    con = sqlite3.connect(old)
    old_columns = [c for c in COLUMNS if c not in ("worker", "run", "extra")]  # an older layout
    con.execute(f"CREATE TABLE cases ({', '.join(f'{c} {COLUMNS[c]}' for c in old_columns)})")
    con.execute("INSERT INTO cases (key, study, status, seconds) VALUES ('k', 's', 'ok', 2.0)")
    con.commit()
    con.close()
    with ResultStore(old, create=False) as store:
        assert [r["key"] for r in store.rows()] == ["k"]
    with ResultStore(old) as store:
        store.record({"key": "k2", "study": "s", "status": "ok"})
    con = sqlite3.connect(old)
    assert con.execute("PRAGMA application_id").fetchone()[0] == APPLICATION_ID
    con.close()


def _corrupt(path: Path) -> None:
    """4 KiB of flipped bytes in the middle of the file (past the header page)."""
    data = bytearray(path.read_bytes())
    start = 4096 if len(data) >= 8192 else len(data) // 2
    for i in range(start, min(len(data), start + 4096)):
        data[i] ^= 0xFF
    path.write_bytes(bytes(data))


def test_a_corrupt_database_is_reported_as_corrupt(database, tmp_path):
    study, db = database
    with ResultStore(db) as store:  # a few pages more, so that the flipped bytes hit the tables
        for i in range(200):
            store.record({"key": f"k{i}", "study": "s", "status": "ok", "message": "x" * 100})
    _corrupt(db)
    before = db.read_bytes()
    for argv in (("show", db), ("export", db, "--out", tmp_path / "x.csv"), ("run", study, "--db", db, "--workers", "0")):
        line = one_line(*run("study", *argv)[::2])
        assert "corrupt" in line and "s.sqlite" in line, line
    assert db.read_bytes() == before and not (tmp_path / "x.csv").exists()
