"""The C build: compiler errors are shown whole, failed builds leave nothing in the cache."""
import pytest

from runtime.cbuild import CompileError, compile_shared


def test_compile_error_is_shown_whole_and_leaves_no_file(tmp_path, monkeypatch):
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    src = tmp_path / "broken.c"
    src.write_text("void f(void) { int x = ; }\n")
    with pytest.raises(CompileError) as info:
        compile_shared([src])
    msg = str(info.value)
    assert "broken.c" in msg and "error" in msg and "expected expression" in msg
    assert list((tmp_path / "cache").iterdir()) == []


def test_compiled_library_is_cached_by_content(tmp_path, monkeypatch):
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    src = tmp_path / "ok.c"
    src.write_text("double twice(double x) { return 2.0 * x; }\n")
    a = compile_shared([src])
    assert compile_shared([src]) == a            # unchanged source: the cached library
    src.write_text("double twice(double x) { return x + x; }\n")
    assert compile_shared([src]) != a            # changed source: a new library
