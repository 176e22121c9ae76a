"""Launch files of many processes, for the scale tests and the scale benchmark (issue 42):
``count`` processes of the installed example package, talkers and listeners in turn, each pair
in a namespace of its own (``/r0/talker0``, ``/r0/listener1``, ``/r1/talker0``, ...)."""

from __future__ import annotations


def many_processes(count: int) -> str:
    """A launch file (XML) starting ``count`` example processes."""
    nodes = []
    for i in range(count):
        executable = "talker" if i % 2 == 0 else "listener"
        nodes.append(f'  <group><push-ros-namespace namespace="r{i // 2}"/>'
                     f'<node pkg="rmw_introspect_examples" exec="{executable}" name="{executable}{i % 2}"/></group>')
    return "<launch>\n" + "\n".join(nodes) + "\n</launch>\n"


def node_names(count: int) -> list[str]:
    """The nodes of :func:`many_processes` ``(count)``, sorted."""
    return sorted(f"/r{i // 2}/{'talker' if i % 2 == 0 else 'listener'}{i % 2}" for i in range(count))
