"""A NoDL document as the golden of an `interfaces` marker: --update-golden writes NoDL, the
test then passes, and drift from the document fails it."""

from __future__ import annotations

import yaml

NODL_TEST = """
@pytest.mark.interfaces("contracts/talker.nodl.yaml", script=NODES + "/talker.py")
def test_talker(interfaces):
    assert "/talker" in interfaces.nodes
"""


def test_a_nodl_golden_is_written_as_nodl_and_checked(project):
    project.test(NODL_TEST)
    created = project.run("--update-golden")
    created.assert_outcomes(passed=1)
    created.stdout.fnmatch_lines(["created  contracts/talker.nodl.yaml"])
    text = project.read("contracts/talker.nodl.yaml")
    assert text.startswith("---\n# node: /talker\nnodl_version: 2\n"), text
    (doc,) = yaml.safe_load_all(text)
    assert doc["publishers"][0]["qos"]["depth"] == 10 and "type_hash" not in text

    project.run().assert_outcomes(passed=1)
    project.write("contracts/talker.nodl.yaml", text.replace("depth: 10\n", "depth: 3\n", 1))
    drifted = project.run()
    drifted.assert_outcomes(failed=1)
    drifted.stdout.fnmatch_lines(["*[[]QOS_DEPTH_INCREASED[]] depth 3 -> 10*",
                                  "*NoDL cannot express type hashes, lifecycle states*"])
