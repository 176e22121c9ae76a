"""Where a top-level block sits in the text of a YAML document, so that a writer can replace
one section of a contract (``nodes``, ``types``) and keep every other byte as it was."""

from __future__ import annotations


def top_level_block(text: str, key: str) -> tuple[list[str], int, int] | None:
    """``(lines, first, end)``: the lines of ``text`` (ends kept) and the block of the
    top-level ``key``, from its key line ``first`` up to ``end`` (exclusive). Comment and blank
    lines right above the next top-level key belong to that key, not to the block. None when
    ``text`` is not a block-style mapping or has no ``key`` at column 0."""
    import yaml  # ~20 ms: only a writer of contracts needs it

    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.YAMLError:
        return None
    if not isinstance(root, yaml.MappingNode) or root.flow_style:
        return None
    lines = text.splitlines(keepends=True)
    pairs = root.value
    for index, (node, _value) in enumerate(pairs):
        if not (isinstance(node, yaml.ScalarNode) and node.value == key):
            continue
        if node.start_mark.column != 0:
            return None
        first = node.start_mark.line
        end = len(lines)
        if index + 1 < len(pairs):
            end = pairs[index + 1][0].start_mark.line
            while end > first + 1 and (lines[end - 1].startswith("#") or not lines[end - 1].strip()):
                end -= 1
        return lines, first, end
    return None
