"""supcoord.instruments: SDSS-V's packaged wok calibrations and kaiju's robot geometry.

The cross-check against kaiju itself is ``benchmarks/kaiju_geometry_check.py`` (it needs kaiju);
here, two of its outputs are pinned as numbers (``KAIJU_GOLDEN``) so the tests need only numpy.
"""

from __future__ import annotations

import csv
import io
import math
from importlib import resources

import numpy as np
import pytest

from supcoord.errors import FormatError, InputError
from supcoord.instruments import (
    INSTRUMENTS,
    InstrumentGeometry,
    fibre_joints,
    fibre_xy,
    load_instrument,
    robot_collision_distance,
    robot_forward,
)
from supcoord.instruments._tables import MAX_BYTES

DATA = resources.files("supcoord.instruments").joinpath("data", "sdss_v")
FILES = [f"{s}_{t}.csv" for s in ("apo", "lco") for t in ("positionerTable", "wokCoords", "fiducialCoords",
                                                            "gfaCoords")]

#: kaiju 1.4.1 RobotGridAPO / RobotGridLCO built from these tables (coordio $WOKCALIB_DIR):
#: robot.setAlphaBeta(alpha, beta); robot.collisionSegWokXYZ, robot.bossWokXYZ (x, y)
KAIJU_GOLDEN = [
    ("sdss-v-apo", 3, "R-1C14", (30.0, 120.0),
     [[15.151407500632788, -25.840159814222424], [22.202504914311362, -12.91015718202275]],
     [22.60743573696189, -12.92116992668214]),
    ("sdss-v-lco", 1157, "R+10C1", (250.0, 35.5),
     [[-186.2730840022464, 196.4099869575669], [-200.34102265373497, 192.05154171828383]],
     [-200.7022552635943, 192.35469356395495]),
]


def _rows(name: str) -> list[dict[str, str]]:
    return list(csv.DictReader(io.StringIO(DATA.joinpath(name).read_text(encoding="utf-8"))))


@pytest.mark.parametrize("name", INSTRUMENTS)
def test_counts_robots_fiducials_gfas(name):
    g = load_instrument(name)
    assert isinstance(g, InstrumentGeometry) and g.name == name
    assert len(g.hole_ids) == len(g.positioner_ids) == 500
    assert len(set(g.hole_ids)) == len(set(g.positioner_ids)) == 500
    assert g.bases.shape == (500, 2) and g.alpha_arm.shape == (500,) and g.beta_segment.shape == (500, 2, 2)
    assert g.obstacle_kinds.count("fiducial") == 60 and g.obstacle_kinds.count("gfa") == 6
    m = len(g.obstacle_kinds)
    assert g.obstacles.shape == (m, 2, 2) and g.obstacle_buffers.shape == (m,) and len(g.obstacle_ids) == m
    assert len(set(g.obstacle_ids)) == m
    assert int(g.has_apogee.sum()) == 298           # 298 ApogeeBoss + 202 Boss robots
    for f in ("metrology", "apogee", "boss"):
        assert g.fibres[f].shape == (500, 2)


@pytest.mark.parametrize("name", INSTRUMENTS)
def test_rows_follow_the_positioner_table(name):
    g = load_instrument(name)
    rows = _rows(f"{name[-3:]}_positionerTable.csv")
    assert g.hole_ids == tuple(r["holeID"] for r in rows)
    assert g.positioner_ids == tuple(int(r["positionerID"]) for r in rows)
    np.testing.assert_array_equal(g.alpha_arm, [float(r["alphaArmLen"]) for r in rows])
    np.testing.assert_array_equal(g.alpha_offset_deg, [float(r["alphaOffset"]) for r in rows])
    np.testing.assert_array_equal(g.fibres["boss"][:, 1], [float(r["bossY"]) for r in rows])


@pytest.mark.parametrize("name", INSTRUMENTS)
def test_measured_arms_are_within_7_2_to_7_6_mm(name):
    arms = load_instrument(name).alpha_arm
    assert 7.2 < arms.min() and arms.max() < 7.6
    assert 7.38 < float(np.median(arms)) < 7.40


def test_kaiju_numbers():
    g = load_instrument("sdss-v-apo")
    end = 16.2 - (math.sqrt(2.0**2 + 0.3**2) - 0.55)          # kaiju robotGrid.py:410-426
    np.testing.assert_allclose(g.beta_segment, np.broadcast_to([[0, 0], [end, 0]], (500, 2, 2)), atol=0)
    assert round(end, 6) == 14.727625
    assert g.robot_buffer == 2.0
    kinds = np.array(g.obstacle_kinds)
    assert set(g.obstacle_buffers[kinds == "fiducial"]) == {3.0} and set(g.obstacle_buffers[kinds == "gfa"]) == {3.0}
    assert g.folded_deg == (10.0, 170.0)
    assert g.alpha_range_deg == (0.0, 360.0) and g.beta_range_deg == (0.0, 360.0)
    assert [round(robot_collision_distance(g, s), 4) for s in (0, 0.1, 1)] == [4.0, 4.0782, 4.7819]
    with pytest.raises(InputError):
        robot_collision_distance(g, -1)
    for key in ("beta_segment", "robot_buffer", "fiducial_buffer", "gfa_buffer", "gfa_segments", "bases",
                "alpha_arm", "fibres", "offsets", "handedness", "alpha_range", "beta_range", "folded"):
        assert ("@" in g.sources[key] and ":" in g.sources[key]) or g.sources[key].startswith("fps_calibrations")
    assert "apo_positionerTable.csv:alphaArmLen" in g.sources["alpha_arm"]


def test_bases_apply_dx_dy_in_the_hole_frame():
    g = load_instrument("sdss-v-apo")
    pos, wok = _rows("apo_positionerTable.csv"), {r["holeID"]: r for r in _rows("apo_wokCoords.csv")}
    for k in (0, 137, 499):
        r, h = pos[k], wok[pos[k]["holeID"]]
        i, j = np.array([float(h["ix"]), float(h["iy"])]), np.array([float(h["jx"]), float(h["jy"])])
        hole = np.array([float(h["xWok"]), float(h["yWok"])])
        expected = hole + float(r["dx"]) * i + float(r["dy"]) * j     # coordio tangentToWok
        np.testing.assert_allclose(g.bases[k], expected, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(g.hole_xy[k], hole)
    # every hole's i = (0, -1), j = (1, 0): dx moves the base along -y, dy along +x
    np.testing.assert_array_equal(g.frames, np.broadcast_to([[0.0, 1.0], [-1.0, 0.0]], (500, 2, 2)))


def test_robot_forward_matches_a_hand_computation():
    g = load_instrument("sdss-v-apo")
    k, alpha, beta = 42, 63.0, 141.0
    r = _rows("apo_positionerTable.csv")[k]
    la, a0, b0 = float(r["alphaArmLen"]), float(r["alphaOffset"]), float(r["betaOffset"])
    ta = math.radians(alpha + a0)                  # the alpha arm's direction in the tangent frame
    tb = math.radians(alpha + a0 + beta + b0)      # the beta arm's direction
    end = 16.2 - (math.sqrt(4.09) - 0.55)

    def focal(tx, ty):                             # tangent -> focal: x_f = ty, y_f = -tx (i=(0,-1), j=(1,0))
        return [g.bases[k][0] + ty, g.bases[k][1] - tx]

    elbow = (la * math.cos(ta), la * math.sin(ta))
    tip = (elbow[0] + end * math.cos(tb), elbow[1] + end * math.sin(tb))
    np.testing.assert_allclose(robot_forward(g, k, alpha, beta), [focal(*elbow), focal(*tip)], atol=1e-12)
    bx, by = float(r["bossX"]), float(r["bossY"])
    boss = (elbow[0] + bx * math.cos(tb) - by * math.sin(tb), elbow[1] + bx * math.sin(tb) + by * math.cos(tb))
    np.testing.assert_allclose(fibre_xy(g, k, alpha, beta), focal(*boss), atol=1e-12)


@pytest.mark.parametrize("name, pid, hole, ab, segment, boss", KAIJU_GOLDEN)
def test_matches_kaiju_pinned_values(name, pid, hole, ab, segment, boss):
    g = load_instrument(name)
    k = g.positioner_ids.index(pid)
    assert g.hole_ids[k] == hole
    np.testing.assert_allclose(robot_forward(g, k, *ab), segment, rtol=0, atol=1e-9)
    np.testing.assert_allclose(fibre_xy(g, k, *ab, fibre="boss"), boss, rtol=0, atol=1e-9)


def test_forward_broadcasts_and_inverse_round_trips():
    g = load_instrument("sdss-v-lco")
    rng = np.random.default_rng(3)
    p = np.arange(500)
    a, b = rng.uniform(0, 360, 500), rng.uniform(5, 175, 500)
    seg = robot_forward(g, p, a, b)
    assert seg.shape == (500, 2, 2)
    np.testing.assert_allclose(seg[17], robot_forward(g, 17, a[17], b[17]), atol=0)
    np.testing.assert_allclose(np.linalg.norm(seg[:, 1] - seg[:, 0], axis=-1), g.beta_segment[0, 1, 0], atol=1e-9)
    for f in ("metrology", "apogee", "boss"):
        xy = fibre_xy(g, p, a, b, f)
        np.testing.assert_allclose(fibre_joints(g, p, xy, f), np.column_stack([a, b]), atol=1e-7)
    assert np.isnan(fibre_joints(g, 0, g.bases[0] + [40.0, 0.0])).all()     # out of reach
    assert robot_forward(g, 0, np.zeros((3, 4)), 180.0).shape == (3, 4, 2, 2)
    with pytest.raises(InputError, match="unknown fibre"):
        fibre_xy(g, 0, 0, 0, fibre="sky")
    for bad in (500, -1, 1.5, [0, 600]):
        with pytest.raises(InputError, match="robot index"):
            robot_forward(g, bad, 0, 0)


def _point_segment(x, a, b):
    t = np.clip(((x - a) * (b - a)).sum(-1) / ((b - a) ** 2).sum(-1), 0, 1)[..., None]
    return np.linalg.norm(x - (a + t * (b - a)), axis=-1)


@pytest.mark.parametrize("name", INSTRUMENTS)
def test_folded_lattice_is_collision_free(name):
    g = load_instrument(name)
    seg = robot_forward(g, np.arange(500), *g.folded_deg)
    # folded, each segment lies in a disc of radius `reach` (< 7.7 mm) around its alpha axis ...
    reach = np.linalg.norm(seg - g.bases[:, None], axis=-1).max()
    assert reach < 7.7
    # ... and the discs are further apart than kaiju's collision distances (even at 1° steps)
    gap = np.linalg.norm(g.bases[:, None] - g.bases[None], axis=-1) + np.eye(500) * 1e3
    assert gap.min() - 2 * reach > robot_collision_distance(g, 1.0)
    obs = g.obstacles
    clearance = _point_segment(g.bases[:, None], obs[None, :, 0], np.where(
        (obs[:, 0] == obs[:, 1]).all(-1)[:, None], obs[:, 1] + 1e-12, obs[:, 1])[None]) - reach
    assert (clearance > g.robot_buffer + g.obstacle_buffers).all()


def test_obstacles_are_the_tables_fiducials_and_kaijus_gfas():
    g = load_instrument("sdss-v-apo")
    fids = _rows("apo_fiducialCoords.csv")
    for k, r in enumerate(fids):
        assert g.obstacle_kinds[k] == "fiducial" and g.obstacle_ids[k] == r["id"]
        np.testing.assert_array_equal(g.obstacles[k], [[float(r["xWok"]), float(r["yWok"])]] * 2)
    gfa = _rows("apo_gfaCoords.csv")
    seg = g.obstacles[60:]
    assert g.obstacle_ids[60:] == tuple(f"GFA{r['id']}" for r in gfa)
    np.testing.assert_allclose(np.linalg.norm(seg.mean(1), axis=-1), 276.23, atol=0.01)   # the GFAs' inner edge
    for s, r in zip(seg, gfa):       # kaiju's GFA segment i faces the table's GFA id i + 1 (within 0.2 deg)
        centre = np.array([float(r["xWok"]), float(r["yWok"])])
        m = s.mean(0)
        assert abs(math.degrees(math.atan2(m[1], m[0]) - math.atan2(centre[1], centre[0]))) < 0.2
    assert int(g.fiducial_watch.sum()) == 42


def test_unknown_instrument_is_a_one_line_input_error():
    with pytest.raises(InputError) as err:
        load_instrument("x")
    assert str(err.value) == "unknown instrument 'x' (known: sdss-v-apo, sdss-v-lco)"
    assert load_instrument("SDSS-V-APO").name == "sdss-v-apo"


def test_arrays_are_read_only():
    g = load_instrument("sdss-v-apo")
    for arr in (g.bases, g.alpha_arm, g.beta_segment, g.fibres["boss"], g.obstacles, g.obstacle_buffers,
                g.frames, g.fiducial_watch):
        with pytest.raises(ValueError):
            arr[..., 0] = 0
    g.fibres["boss"] = None                                 # a caller's dict, not the cache's
    assert load_instrument("sdss-v-apo").fibres["boss"] is not None


def _copy_data(tmp_path):
    for f in FILES:
        (tmp_path / f).write_bytes(DATA.joinpath(f).read_bytes())
    return tmp_path


def test_missing_column_names_file_and_field(tmp_path):
    d = _copy_data(tmp_path)
    p = d / "apo_positionerTable.csv"
    p.write_text(p.read_text().replace("alphaArmLen", "alphaArmLength", 1))
    with pytest.raises(FormatError) as err:
        load_instrument("sdss-v-apo", data_dir=d)
    assert err.value.where == "apo_positionerTable.csv" and err.value.value == "alphaArmLen"
    assert "missing column 'alphaArmLen'" in str(err.value) and "\n" not in str(err.value)


def test_bad_value_names_file_line_column_and_value(tmp_path):
    d = _copy_data(tmp_path)
    p = d / "lco_wokCoords.csv"
    lines = p.read_text().splitlines(keepends=True)
    cells = lines[3].split(",")
    assert lines[0].split(",")[7] == "xWok"
    cells[7] = "abc"
    lines[3] = ",".join(cells)
    p.write_text("".join(lines))
    with pytest.raises(FormatError) as err:
        load_instrument("sdss-v-lco", data_dir=d)
    assert err.value.where == "lco_wokCoords.csv line 4, column xWok" and err.value.value == "abc"


def test_oversized_or_missing_files_are_format_errors(tmp_path):
    d = _copy_data(tmp_path)
    (d / "apo_gfaCoords.csv").write_bytes(b"x" * (MAX_BYTES + 1))
    with pytest.raises(FormatError, match="larger than"):
        load_instrument("sdss-v-apo", data_dir=d)
    (d / "lco_fiducialCoords.csv").unlink()
    with pytest.raises(FormatError, match="cannot read") as err:
        load_instrument("sdss-v-lco", data_dir=d)
    assert err.value.where == "lco_fiducialCoords.csv"


def test_packaged_data_is_attributed():
    names = {p.name for p in DATA.iterdir()}
    assert set(FILES) <= names and "README.md" in names
    text = DATA.joinpath("README.md").read_text(encoding="utf-8")
    assert "sdss/fps_calibrations" in text and "2025.12.04" in text
    assert "e7867464fe410188e8aa93cbcbd4eb113afed005" in text
    assert DATA.joinpath("apo_positionerTable.csv").read_text().startswith("id,site,holeID,id.1,positionerID,")
