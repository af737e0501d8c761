"""``.gen`` files as libFAUDES reads them: every layout of ``tests/data/gen`` (written for
these tests, following the grammar of docs/formats.md) and random files mixing those
layouts are read alike by supcoord and by libFAUDES itself (``faudes.Generator`` and
``faudes.System``): the same counts, the same transitions under the same state labels,
equal languages, the same controllable events; what libFAUDES refuses, supcoord refuses
with one line naming the file, the line and the token.  The documented differences:
supcoord generators are deterministic (two initial states or two transitions on one
event from one state are refused), a file without an initial state is the empty
generator, and a file whose native layout breaks is refused where libFAUDES reads an
empty generator."""

from __future__ import annotations

import re
from pathlib import Path

import faudes
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from oracle import to_faudes

from supcoord.des.io.gen_file import read_gen, read_gen_flat
from supcoord.des.io.gen_parser import parse_text_by_token
from supcoord.errors import FormatError, NondeterminismError

DATA = Path(__file__).resolve().parents[1] / "data" / "gen"
FILES = sorted(DATA.glob("*.gen"))
#: the controllable events of the wrapper layouts, which libFAUDES's System cannot read
WRAPPED = {"cgenerator.gen": {"start", "repair"}, "cgenerator_attributes.gen": {"alpha", "lambda"},
           "agenerator.gen": set()}


def faudes_read(path, cls="Generator"):
    try:
        return getattr(faudes, cls)(str(path))
    except Exception:  # libFAUDES refuses the file
        return None


def labels(g):
    """A state's label: its name, or its libFAUDES index."""
    return (lambda q: g.state_names[q]) if g.state_names else (lambda q: str(q + 1))


def agree(ours, theirs) -> None:
    """The same generator: states, transitions, initial and marked states under the same labels."""
    lists = theirs.ToLists()
    states, events, trans, init, marked = lists[0], lists[1], lists[-3], lists[-2], lists[-1]
    assert set(ours.events) == {str(e) for e in events}
    if not init:  # the empty language: supcoord's empty generator
        assert ours.n_states == 0
        return
    lab = labels(ours)
    assert ours.n_states == len(states)
    assert {(lab(a), e, lab(b)) for a, e, b in ours.transitions()} == {(str(a), str(e), str(b)) for a, e, b in trans}
    assert [lab(ours.init)] == [str(q) for q in init]
    assert {lab(q) for q in ours.marked} == {str(q) for q in marked}


def same_language(ours, theirs) -> bool:
    """``L`` and ``Lm`` equal (libFAUDES's ``LanguageEquality``, on prefix closures for ``L``)."""
    a, b = to_faudes(ours), faudes.Generator(theirs)
    if not faudes.LanguageEquality(a, b):
        return False
    faudes.PrefixClosure(a)
    faudes.PrefixClosure(b)
    return bool(faudes.LanguageEquality(a, b))


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_every_layout_reads_as_libfaudes_reads_it(path):
    ours = read_gen(path)
    theirs = faudes_read(path)
    assert theirs is not None, f"libFAUDES refuses {path.name}"
    agree(ours, theirs)
    assert ours.n_states and same_language(ours, theirs)
    system = faudes_read(path, "System")
    if path.name in WRAPPED:  # faudes.System reads no wrapper; the wrapper's <Controllable> is read
        assert system is None and ours.controllable == WRAPPED[path.name]
    else:
        assert ours.controllable == {str(e) for e in system.ToLists()[2]}


def test_the_layouts_mean_what_their_comments_say():
    g = read_gen(DATA / "event_attributes.gen")
    assert g.controllable == {"xml_on", "set_option", "forcible", "hex_on"}  # +c+ and +Cc+ clear the flag
    g = read_gen(DATA / "implicit_indices.gen")
    assert g.n_states == 7 and g.state_names is not None and g.state_names[0] == "7"
    g = read_gen(DATA / "implicit_names.gen")
    assert g.state_names == ["home", "away", "far", "back"]
    g = read_gen(DATA / "state_attributes.gen")
    assert g.state_names == ["idle", "busy", "down", "repair"] and len(g.marked) == 2
    g = read_gen(DATA / "index_suffix.gen")
    assert g.state_names == ["low", "mid", "high"] and g.init == 0
    assert read_gen(DATA / "cgenerator.gen").name == "cgenerator"


# -- refusals: one line naming the file, the line and the token ---------------------------------

REFUSED = [
    ("<Generator> <Alphabet> a </Alphabet> <States> x x </States> <TransRel> </TransRel> </Generator>",
     "appears twice", "x"),
    ("<Generator> <Alphabet> a b </Alphabet> <States> x y </States>\n<TransRel>\nx c y\n</TransRel> </Generator>",
     "line 3", "'c'"),
    (("<Generator> <Alphabet> a </Alphabet> <States> x y </States> <TransRel> x a y </TransRel>\n"
     "<InitStates> q </InitStates> </Generator>"), "line 2", "'q'"),
    (("<Generator> <Alphabet> a </Alphabet> <States> x y </States> <TransRel> x a y </TransRel>\n"
     "<InitStates> 9 </InitStates> </Generator>"), "line 2", "'9'"),
    (("<Generator> <Alphabet> a </Alphabet> <States> 1 2 </States> <TransRel> 1 a 2 </TransRel>\n"
     "<InitStates> <Foo> 2 </Foo> 1 </InitStates> </Generator>"), "line 2", "<Foo>"),
    ("<Generator> <Alphabet> a b </Alphabet> <States> 1 2 </States> <TransRel>\n1 a 2 2 b\n</TransRel> </Generator>",
     "line 3", "</TransRel>"),
    ("<Generator> <Alphabet> a </Alphabet> <States> x#3 y </States> <TransRel> </TransRel> </Generator>",
     "line 1", "#"),
    ('<Generator> <Alphabet> a </Alphabet> <States> "x y" </States> <TransRel> </TransRel> </Generator>',
     "line 1", "'x y'"),
    ("</Foo>\n<Generator> <Alphabet> a </Alphabet> <TransRel> </TransRel> </Generator>", "line 1", "</Foo>"),
    ("% a comment with <Generator> in it\n<Generator> <T> </T> </Generator>", "line 1", "<"),
    ("<Generator> <Alphabet> a </Alphabet> <States> 1 </States> <TransRel> 1 a 1 </TransRel>", "missing", "Generator"),
    ("<Graph> </Graph>", "expected <Generator>", "<Generator>"),
    (("<Generator> <Alphabet> a +C+ a </Alphabet> <States> 1 2 </States> <TransRel> 1 a 2 </TransRel>\n"
     "<InitStates> 1 </InitStates> <MarkedStates> 3 </MarkedStates> </Generator>"), "line 2", "'3'"),
]


@pytest.mark.parametrize("text,line,token", REFUSED, ids=range(len(REFUSED)))
def test_what_libfaudes_refuses_is_refused_naming_file_line_and_token(tmp_path, text, line, token):
    path = tmp_path / "bad.gen"
    path.write_text(text)
    assert faudes_read(path) is None and faudes_read(path, "System") is None
    with pytest.raises(FormatError) as info:
        read_gen(path)
    message = str(info.value)
    assert info.value.where == str(path) and message.startswith(f"{path}: ") and "\n" not in message
    assert line in message and token in message, message


@pytest.mark.parametrize("text", [
    ('<Generator> "name" "stray" <Alphabet> a </Alphabet> <States> 1 </States> <TransRel> 1 a 1 </TransRel> '
    "<InitStates> 1 </InitStates> </Generator>"),
    ('<Generator> "name" <Alphabet> a b </Alphabet> cb13-5 +C+ <States> 1 </States> <TransRel> 1 a 1 </TransRel> '
    "<InitStates> 1 </InitStates> </Generator>"),
    ('<Generator> "name" <States> 1 </States> <Alphabet> a </Alphabet> <TransRel> 1 a 1 </TransRel> '
    "<InitStates> 1 </InitStates> </Generator>"),
])
def test_a_broken_native_layout_is_refused_where_libfaudes_reads_nothing(tmp_path, text):
    path = tmp_path / "broken.gen"
    path.write_text(text)
    theirs = faudes_read(path)
    assert theirs is not None and theirs.Size() == 0  # libFAUDES: an empty generator, silently
    with pytest.raises(FormatError, match=r"line 1: expected <TransRel>, found ('stray'|'cb13-5'|<Alphabet>)"):
        read_gen(path)


# -- random files mixing the layouts, against libFAUDES ---------------------------------------

NAMES = ["idle", "busy", "s", "q1", "x_y", "2nd", "+p", "true"]
EVENTS = ["a", "b", "go", "10", "x<y", "e.f"]
ATTRIBUTES = ["", "", "", "0x01", "+P+", "true", "-3", "<Foo> 1 \"x\" </Foo>", "+C+"]
EVENT_FLAGS = ["", "", "+C+", "+c+", "+Cc+", "0x0b", "0x00", "+CF+", "true"]


def word(name: str) -> str:
    """A name as a token: bare when libFAUDES reads it back as that string, else quoted."""
    plain = re.fullmatch(r"[A-Za-z][A-Za-z0-9_.]*", name) and name not in ("true", "false", "inf")
    return name if plain else '"' + name.replace("<", "&lt;") + '"'


@st.composite
def gen_texts(draw):
    """The text of a ``.gen`` file in a random layout, and the events its wrapper marks controllable."""
    events = draw(st.lists(st.sampled_from(EVENTS), min_size=1, max_size=4, unique=True))
    alphabet = " ".join(f"{word(e)} {draw(st.sampled_from(EVENT_FLAGS))}" for e in events)
    scheme = draw(st.sampled_from(["index", "name", "mixed", "consecutive", "suffix", "none"]))
    n = draw(st.integers(1, 4))
    states: list[tuple[int, str | None]] = []  # (libFAUDES index, name)
    if scheme == "index":
        states = [(i, None) for i in draw(st.lists(st.integers(1, 7), min_size=n, max_size=n, unique=True))]
    elif scheme == "name":
        states = [(k + 1, nm) for k, nm in enumerate(draw(st.lists(st.sampled_from(NAMES), min_size=n, max_size=n,
                                                                   unique=True)))]
    elif scheme == "mixed":
        states = [(k + 1, None if draw(st.booleans()) else NAMES[k]) for k in range(n)]
    elif scheme == "consecutive":
        states = [(k + 1, None) for k in range(n)]
    elif scheme == "suffix":
        idx = draw(st.permutations(range(1, n + 1)))
        states = [(i, NAMES[k]) for k, i in enumerate(idx)]
    if scheme == "consecutive":
        listed = f"<Consecutive> 1 {n} </Consecutive>"
    elif scheme == "suffix":
        listed = " ".join(f"{nm}#{i}" for i, nm in states)
    else:
        listed = " ".join((str(i) if nm is None else word(nm)) + " " + draw(st.sampled_from(ATTRIBUTES))
                          for i, nm in states)

    def ref():
        if states and draw(st.integers(0, 14)) > 0:
            i, nm = draw(st.sampled_from(states))
            return str(i) if nm is None or draw(st.integers(0, 3)) == 0 else word(nm)
        return draw(st.sampled_from(["8", "9", "fresh", "other"]))  # a state the file does not list

    def event():
        return word(draw(st.sampled_from(events))) if draw(st.integers(0, 20)) else "zz"

    trans = [f"{ref()} {event()} {ref()} {draw(st.sampled_from(['', '', '0x03', '+x+']))}"
             for _ in range(draw(st.integers(0, 6)))]
    init = " ".join(ref() for _ in range(draw(st.sampled_from([1, 1, 1, 0, 2]))))
    marked = " ".join(ref() for _ in range(draw(st.integers(0, 3))))
    short = draw(st.booleans())
    A, S, T, I, M = ("A", "S", "T", "I", "M") if short else ("Alphabet", "States", "TransRel", "InitStates",
                                                              "MarkedStates")
    sections = [f"<{A}> {alphabet} </{A}>" if draw(st.integers(0, 5)) else "",
                f"<{S}> {listed} </{S}>" if scheme != "none" else "",
                f"<{T}>\n" + "\n".join(trans) + f"\n</{T}>",
                f"<{I}> {init} </{I}>" if draw(st.integers(0, 5)) else "",
                f"<{M}> {marked} </{M}>"]
    if draw(st.integers(0, 15)) == 0:  # sections out of order
        sections[1], sections[2] = sections[2], sections[1]
    body = "<Generator> " + word("g") + "\n" + "\n".join(sections) + "\n</Generator>\n"
    wrapper = draw(st.sampled_from(["", "", "cGenerator", "aGenerator", "lead", "trail"]))
    flagged = set(draw(st.lists(st.sampled_from(events), max_size=2)))
    if wrapper == "cGenerator":
        body = f"<cGenerator>\n{body}<Controllable> {' '.join(map(word, flagged))} </Controllable>\n</cGenerator>\n"
    elif wrapper == "aGenerator":
        body = f"<aGenerator>\n{body}<StateAttributes> 1 2 </StateAttributes>\n</aGenerator>\n"
    elif wrapper == "lead":
        body = '5 "x" % a comment\n<Note> <a/> text </Note>\n' + body
    elif wrapper == "trail":
        body += '<y_lo_ev> "a" </y_lo_ev> stray "unterminated\n'
    return body, (flagged if wrapper == "cGenerator" else None)


@settings(max_examples=300, deadline=None, suppress_health_check=list(HealthCheck), database=None)
@given(gen_texts())
@pytest.mark.slow
def test_random_layouts_read_as_libfaudes_reads_them(tmp_path_factory, case):
    text, flagged = case
    path = tmp_path_factory.mktemp("gen") / "g.gen"
    path.write_text(text, encoding="latin-1")
    theirs = faudes_read(path)
    try:
        ours, error = read_gen(path), None
    except (FormatError, NondeterminismError) as exc:
        ours, error = None, exc
    # the token-by-token reading and the column-at-a-time one agree
    try:
        slow = parse_text_by_token(text, str(path)).to_generator()
    except (FormatError, NondeterminismError) as exc:
        assert error is not None and str(exc) == str(error)
    else:
        assert ours is not None and ours.same_as(slow) and ours.state_names == slow.state_names
    if theirs is None:
        assert error is not None, f"supcoord reads what libFAUDES refuses:\n{text}"
        assert isinstance(error, FormatError) and error.where == str(path) and "line " in str(error)
        return
    if error is not None:
        lists = theirs.ToLists()
        if isinstance(error, NondeterminismError):  # documented: deterministic generators only
            assert len(lists[3]) > 1 or len({(a, e) for a, e, _ in lists[2]}) < len(lists[2]), text
        else:  # documented: a broken native layout, which libFAUDES reads as an empty generator
            assert theirs.Size() == 0 and "<TransRel>" in str(error), (str(error), text)
        return
    agree(ours, theirs)
    system = faudes_read(path, "System")
    if system is not None:
        assert ours.controllable == {str(e) for e in system.ToLists()[2]}
    elif flagged is not None:
        assert flagged & set(ours.events) <= ours.controllable


def test_large_files_take_the_column_reading_and_agree_with_the_token_reading(tmp_path):
    """A generator written by libFAUDES (named states, transitions by index) read both ways."""
    s = faudes.System()
    ev = [s.InsControllableEvent(f"c{k}") if k % 2 else s.InsUncontrollableEvent(f"u{k}") for k in range(6)]
    x = [s.InsState(f"{k}|{k % 7}") for k in range(400)]
    for k in range(400):
        for j in range(3):
            s.SetTransition(x[k], ev[(k + j) % 6], x[(k * 7 + j) % 400])
    s.SetInitState(x[0])
    s.SetMarkedState(x[5])
    path = tmp_path / "big.gen"
    s.Write(str(path))
    text = path.read_text(encoding="latin-1")
    fast, slow = read_gen_flat(path), parse_text_by_token(text, str(path))
    assert fast.state_names == slow.state_names and fast.to_generator().same_as(slow.to_generator())
    agree(fast.to_generator(), faudes.System(str(path)))
