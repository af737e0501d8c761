"""Problems shared by several test files: small PROBLEM.json dicts, the oracle's plan of one,
and a hypothesis strategy of mutated problem files (for fuzzing the readers)."""

import copy

from hypothesis import strategies as st

from supcoord.testing.oracle import oracle_moves

ROTARY = {
    "layout": {"kind": "hex", "rings": 1, "pitch": 22.4},
    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    "collision": {"buffer": 2.0},
    "start": [0, 0, 0, 0, 0, 0, 0],
    "target": [6, 6, 6, 6, 6, 6, 6],
    "priority": [1, 2, 3, 4, 5, 6, 7],
}
ALPHA_BETA = {
    "layout": {"kind": "points", "xy": [[0, 0], [22.4, 0], [11.2, 19.4]]},
    "kinematics": {"kind": "alpha-beta", "alpha": 7.4, "beta": 15.0, "alpha_steps": 12, "beta_steps": 7,
                   "beta_range": [0, 180]},
    "collision": {"buffer": 2.0},
    "start": [[0, 6], [0, 6], [0, 6]],
    "target": [[3, 3], [6, 0], [9, 6]],
}
SDSS_SHORT = {
    "preset": "sdss-v",
    "layout": {"kind": "hex", "rings": 1},
    "kinematics": {"alpha_steps": 12, "beta_steps": 7},
    "start": [[1, 6]] * 7,
    "target": [[1, 6]] * 7,
}

# the seed paper's picture: three rotary positioners in a row, arms long enough to meet
THREE = {
    "layout": {"kind": "points", "xy": [[0, 0], [22.4, 0], [44.8, 0]]},
    "kinematics": {"kind": "rotary", "arm": 15.0, "steps": 12},
    "collision": {"buffer": 2.0},
    "start": [0, 0, 0],
    "target": [6, 6, 6],
    "priority": [1, 2, 3],
}


def oracle_plan_moves(problem):
    """A shortest single-move sequence start → target of the independent oracle (its own
    geometry and search, none of the planner's tables), or None."""
    return oracle_moves(problem.to_json())


# --- fuzzing: any mutation of a valid file raises only InputError/FormatError --------------

json_values = st.recursive(
    st.none() | st.booleans() | st.integers(-10**20, 10**20) | st.floats(allow_nan=True) | st.text(max_size=5),
    lambda children: st.lists(children, max_size=4) | st.dictionaries(st.text(max_size=5), children, max_size=3),
    max_leaves=8,
)
small_values = st.sampled_from([0, 1, -1, 2, 3, 6, 7, 11, 12, 13, 0.5, 1e308, -0.0, True, None, "x", [], {}, [0, 0],
                                [1, 2, 3], "hex", "points", "rotary", "alpha-beta"])


def _paths(node, prefix=()):
    yield prefix
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from _paths(v, prefix + (i,))


@st.composite
def mutated_problems(draw):
    data = copy.deepcopy(draw(st.sampled_from([ROTARY, ALPHA_BETA, SDSS_SHORT])))
    for _ in range(draw(st.integers(1, 3))):
        paths = [p for p in _paths(data) if p]
        if not paths:
            break
        path = draw(st.sampled_from(paths))
        action = draw(st.sampled_from(["replace", "replace", "small", "delete", "append"]))
        *head, last = path
        node = data
        for key in head:
            node = node[key]
        if action == "delete":
            del node[last]
        elif action == "append" and isinstance(node[last], list):
            node[last].append(copy.deepcopy(draw(small_values)))
        elif action == "small":
            node[last] = copy.deepcopy(draw(small_values))
        else:
            node[last] = draw(json_values)
    return data
