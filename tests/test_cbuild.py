"""The C build: compiler errors are shown whole, failed builds leave nothing in the cache, a damaged
library is rebuilt before it is ever loaded, an unusable cache is one line."""
import pytest

from runtime.cbuild import (
    CacheError,
    CompileError,
    cache_dir,
    compile_shared,
    is_intact,
)


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


def test_damaged_library_is_rebuilt_once_before_any_load(tmp_path, monkeypatch, capsys):
    """A truncated or corrupted cached library (dlopen of it can SIGBUS) is found by the size and
    sha256 recorded beside it, and rebuilt; nothing here ever loads it."""
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    src = tmp_path / "ok.c"
    src.write_text("double twice(double x) { return 2.0 * x; }\n")
    lib = compile_shared([src])
    good = lib.read_bytes()
    assert is_intact(lib)
    for damage in (good[: len(good) // 2], good[:-1] + bytes([good[-1] ^ 1])):
        lib.write_bytes(damage)
        assert not is_intact(lib)
        assert compile_shared([src]) == lib and is_intact(lib)
        assert "damaged" in capsys.readouterr().err
    compile_shared([src])
    assert "damaged" not in capsys.readouterr().err
    lib.with_name(lib.name + ".sha256").unlink()           # no stamp: not trusted either
    assert compile_shared([src]) == lib and is_intact(lib)
    assert sorted(p.name for p in lib.parent.iterdir()) == [lib.name, lib.name + ".sha256"]


def test_an_edited_header_rebuilds(tmp_path, monkeypatch):
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    (tmp_path / "k.h").write_text("#define K 2.0\n")
    src = tmp_path / "k.c"
    src.write_text('#include "k.h"\ndouble k(void) { return K; }\n')
    a = compile_shared([src], include_dirs=(tmp_path,))
    (tmp_path / "k.h").write_text("#define K 3.0\n")
    assert compile_shared([src], include_dirs=(tmp_path,)) != a


@pytest.mark.parametrize("where", ["file", "under-a-file"])
def test_unusable_cache_is_a_one_line_user_error(tmp_path, monkeypatch, where):
    blocker = tmp_path / "blocker"
    blocker.write_text("x")
    monkeypatch.setenv("LEVITRON_CACHE", str(blocker if where == "file" else blocker / "sub"))
    with pytest.raises(CacheError) as info:
        cache_dir()
    msg = str(info.value)
    assert "\n" not in msg and "LEVITRON_CACHE" in msg and "writable folder" in msg
