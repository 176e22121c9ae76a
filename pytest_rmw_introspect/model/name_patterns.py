"""Patterns of ROS names matched in linear time: ``*`` in a name segment, ``**`` for any
number of segments (a parameters file's section keys).

A regular expression such as ``[^/]*a[^/]*a[^/]*b`` backtracks catastrophically (a pattern
``/*a*a*a*a*a*a*a*a*b`` took 68 s against one 60-character node name: issue 50, N17 and N26).
Here a segment pattern is its literal pieces between the ``*``: the first must start the
segment, the last end it, and each other is found at its leftmost place after the one before
(leftmost is never worse for what follows), so a match costs one scan of the name. Segments
are matched as a set of positions in the pattern (``**`` keeps its place or moves on), so a key
with many ``**`` costs at most (segments x tokens, a run of ``**`` one token), never one try per
way of splitting the name.
"""

from __future__ import annotations

#: the token of a parameters file's section key that stands for any number of segments
ANY_SEGMENTS = "**"


def segment_matches(pattern: str, text: str) -> bool:
    """Whether ``text`` is ``pattern`` with each ``*`` replaced by any run of characters."""
    first, *pieces = pattern.split("*")
    if not pieces:
        return pattern == text
    last = pieces.pop()
    if len(text) < len(first) + len(last) or not text.startswith(first) or not text.endswith(last):
        return False
    position, end = len(first), len(text) - len(last)
    for piece in pieces:
        found = text.find(piece, position, end)
        if found < 0:
            return False
        position = found + len(piece)
    return True


def name_matches(pattern: str, fqn: str) -> bool:
    """Whether the fully qualified ``fqn`` matches ``pattern`` (``*``: any run of characters
    but ``/``), as an ``unstable_names`` pattern matches a node name."""
    wanted, have = pattern.split("/"), fqn.split("/")
    return len(wanted) == len(have) and all(segment_matches(w, h) for w, h in zip(wanted, have, strict=True))


def section_key_matches(key: str, fqn: str) -> bool:
    """Whether a parameters file's section ``key`` applies to the node ``fqn``: its segments
    with ``*`` (any run of characters but ``/``) and ``**`` (any number of non-empty segments)."""
    tokens: list[str] = []
    for token in key.strip("/").split("/"):
        if token and not (token == ANY_SEGMENTS and tokens[-1:] == [ANY_SEGMENTS]):  # `**/**` is `**`
            tokens.append(token)
    if not tokens:
        return fqn == "/"
    if not fqn.startswith("/"):
        return False
    states = _closure({0}, tokens)
    for segment in fqn[1:].split("/"):
        moved: set[int] = set()
        for state in states:
            if state == len(tokens):
                continue
            token = tokens[state]
            if token == ANY_SEGMENTS:
                if segment:
                    moved.add(state)
            elif segment_matches(token, segment):
                moved.add(state + 1)
        if not moved:
            return False
        states = _closure(moved, tokens)
    return len(tokens) in states


def _closure(states: set[int], tokens: list[str]) -> set[int]:
    """``states`` and every state a ``**`` that matches no segment reaches from them (each
    state visited once: a run of ``**`` is walked once, not once per state in it)."""
    out: set[int] = set()
    for state in sorted(states):
        while state not in out:
            out.add(state)
            if state == len(tokens) or tokens[state] != ANY_SEGMENTS:
                break
            state += 1
    return out
