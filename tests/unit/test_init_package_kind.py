"""`rmw-introspect init` tells what kind of package it wrote contracts for (the wiring it prints)."""

from pytest_rmw_introspect.cli.init import package_build_type


def test_init_tells_the_package_kind_from_its_sources_its_install_or_its_console_scripts(tmp_path):
    source, elsewhere, prefix = tmp_path / "src", tmp_path / "out", tmp_path / "prefix"
    source.mkdir()
    (source / "package.xml").write_text("<package><export><build_type>ament_cmake</build_type></export></package>")
    assert package_build_type("pkg", source, []) == "ament_cmake"  # init run in the package
    assert package_build_type("pkg", elsewhere, []) == "ament_python"  # no ament index entry: `pip install -e .`
    (prefix / "share" / "ament_index" / "resource_index" / "packages").mkdir(parents=True)
    (prefix / "share" / "ament_index" / "resource_index" / "packages" / "pkg").write_text("")
    assert package_build_type("pkg", elsewhere, [prefix]) is None  # installed, kind unknown
    (prefix / "share" / "pkg").mkdir()
    (prefix / "share" / "pkg" / "package.xml").write_text("<package><export><build_type>ament_cmake</build_type></export></package>")
    assert package_build_type("pkg", elsewhere, [prefix]) == "ament_cmake"
