"""Names matched by patterns in linear time (model/name_patterns.py, issue 50, N17 and N26):
the same answers as the regular expressions they replace, on random names, patterns and keys,
and no time that grows with the number of `*` or `**`."""

from __future__ import annotations

import random
import re
import time

import pytest

from pytest_rmw_introspect.model.name_patterns import name_matches, section_key_matches, segment_matches


def _reference_name(pattern: str) -> re.Pattern[str]:
    """The regular expression `unstable_names` patterns were (`*`: any run but `/`)."""
    return re.compile("[^/]*".join(re.escape(part) for part in pattern.split("*")))


def _reference_key(key: str) -> re.Pattern[str]:
    """The regular expression parameters-file section keys were (`**`: any number of segments)."""
    tokens = [t for t in key.strip("/").split("/") if t]
    parts = ["(?:/[^/]+)*" if t == "**" else "/" + re.escape(t).replace(r"\*", "[^/]*") for t in tokens]
    return re.compile("".join(parts) or "/")


def test_the_same_answers_as_the_regular_expressions_on_random_inputs():
    rng = random.Random(50)
    for _ in range(4000):
        name = "/" + "".join(rng.choice("ab/") for _ in range(rng.randint(0, 8)))
        pattern = "/" + "".join(rng.choice("ab*/") for _ in range(rng.randint(0, 7)))
        key = "".join(rng.choice(["a", "b", "*", "**", "/", "/**/", "ab"]) for _ in range(rng.randint(0, 6)))
        assert name_matches(pattern, name) == (_reference_name(pattern).fullmatch(name) is not None), (pattern, name)
        assert section_key_matches(key, name) == (_reference_key(key).fullmatch(name) is not None), (key, name)


@pytest.mark.parametrize(("pattern", "text", "matches"), [
    ("x_*", "x_", True), ("*_*", "_", True), ("a*a", "a", False), ("a*b*a", "aba", True), ("ab*ba", "aba", False),
    ("*", "", True), ("", "", True), ("", "a", False),
])
def test_a_segment_pattern(pattern, text, matches):
    assert segment_matches(pattern, text) is matches


def test_the_time_does_not_grow_with_the_stars():
    began = time.monotonic()
    assert not name_matches("/" + "*a" * 200 + "*b", "/" + "a" * 2000)
    assert not section_key_matches("/**" * 500 + "/b", "/" + "/".join(["a"] * 200))
    assert time.monotonic() - began < 1.0
