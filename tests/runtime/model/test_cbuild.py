"""The C build: compiler errors are shown whole, failed builds leave nothing in the cache, a damaged
library is rebuilt before it is ever loaded, an unusable cache is one line."""
import pytest

from levitron.runtime.model.cbuild import (
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


def _sources(folder, k: str):
    """Two libraries' sources in `folder`: a.c and b.c each with common.c, which includes k.h."""
    (folder / "k.h").write_text(f"#define K {k}\n")
    (folder / "common.c").write_text('#include "k.h"\ndouble k(void) { return K; }\n')
    (folder / "a.c").write_text("double k(void);\ndouble a(void) { return k() + 1.0; }\n")
    (folder / "b.c").write_text("double k(void);\ndouble b(void) { return k() + 2.0; }\n")
    return [folder / "a.c", folder / "common.c"], [folder / "b.c", folder / "common.c"]


def _call(lib, name):
    import ctypes
    fn = getattr(ctypes.CDLL(str(lib)), name)
    fn.restype = ctypes.c_double
    return fn()


def test_a_source_shared_by_two_libraries_is_compiled_once(tmp_path, monkeypatch):
    """Libraries of several sources link cached objects (runtime/csrc/integrators.c is compiled
    once for every model): common.c's object serves both libraries, and an edited header that
    common.c includes gives it a new object and both libraries new values."""
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    src = tmp_path / "src"
    src.mkdir()
    lib_a, lib_b = _sources(src, "2.0")
    a = compile_shared(lib_a, include_dirs=(src,))
    objects = {p.name: p.stat().st_ino for p in (tmp_path / "cache" / "obj").glob("*.o")}
    assert len(objects) == 2 and all(map(is_intact, (tmp_path / "cache" / "obj").glob("*.o")))
    b = compile_shared(lib_b, include_dirs=(src,))
    after = {p.name: p.stat().st_ino for p in (tmp_path / "cache" / "obj").glob("*.o")}
    assert len(after) == 3 and all(after[n] == ino for n, ino in objects.items())   # reused as is
    assert (_call(a, "a"), _call(b, "b")) == (3.0, 4.0)
    (src / "k.h").write_text("#define K 5.0\n")       # seen by common.c only through the preprocessor
    a2, b2 = compile_shared(lib_a, include_dirs=(src,)), compile_shared(lib_b, include_dirs=(src,))
    assert a2 != a and b2 != b
    assert len(list((tmp_path / "cache" / "obj").glob("*.o"))) == 4       # one new common.c object
    assert (_call(a2, "a"), _call(b2, "b")) == (6.0, 7.0)


def test_linked_library_is_the_one_step_build_byte_for_byte(tmp_path, monkeypatch):
    import subprocess

    from levitron.runtime.model.cbuild import DEFAULT_FLAGS, compiler
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    lib_a, _ = _sources(tmp_path, "2.0")
    one = tmp_path / "one.so"
    subprocess.run([compiler(), *DEFAULT_FLAGS, f"-I{tmp_path}", "-o", str(one), *map(str, lib_a), "-lm"],
                   check=True)
    assert compile_shared(lib_a, include_dirs=(tmp_path,)).read_bytes() == one.read_bytes()


def test_damaged_object_is_rebuilt(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    lib_a, lib_b = _sources(tmp_path, "2.0")
    compile_shared(lib_a, include_dirs=(tmp_path,))
    objects = sorted((tmp_path / "cache" / "obj").glob("*.o"))
    for obj in objects:
        obj.write_bytes(obj.read_bytes()[:100])
        assert not is_intact(obj)
    b = compile_shared(lib_b, include_dirs=(tmp_path,))     # needs common.c's object: rebuilt
    assert "damaged" in capsys.readouterr().err
    assert _call(b, "b") == 4.0
    assert sum(map(is_intact, objects)) == 1                 # common.c's; a.c's is not needed by b


def test_a_cache_removed_mid_compile_is_named_not_ld(tmp_path, monkeypatch):
    """Not "ld returned 1" when the cache was deleted while the compiler ran. A fake
    compiler removes the output's folder, as a concurrent `make clean-cache` would."""
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    fake = tmp_path / "fakecc"
    fake.write_text('#!/bin/sh\nif [ "$1" = "--version" ]; then echo fakecc 1; exit 0; fi\n'
                    'while [ $# -gt 0 ]; do if [ "$1" = "-o" ]; then out="$2"; fi; shift; done\n'
                    'rm -rf "$(dirname "$out")"\necho "collect2: error: ld returned 1 exit status" >&2\n'
                    'exit 1\n')
    fake.chmod(0o755)
    monkeypatch.setenv("CC", str(fake))
    src = tmp_path / "ok.c"
    src.write_text("double twice(double x) { return 2.0 * x; }\n")
    with pytest.raises(CacheError, match="was removed while the C compiler ran") as info:
        compile_shared([src])
    assert "\n" not in str(info.value)


def test_a_folder_where_the_library_belongs_is_named(tmp_path, monkeypatch):
    """Not "cache not writable" where the .so path is a folder."""
    from levitron.runtime.model.cbuild import DEFAULT_FLAGS, source_hash
    monkeypatch.setenv("LEVITRON_CACHE", str(tmp_path / "cache"))
    src = tmp_path / "ok.c"
    src.write_text("double twice(double x) { return 2.0 * x; }\n")
    (cache_dir() / f"lev_{source_hash([src], DEFAULT_FLAGS)}.so").mkdir()
    with pytest.raises(CacheError, match="is a folder where the compiled library belongs"):
        compile_shared([src])


def test_locked_excludes_a_second_holder_until_released(tmp_path):
    """cbuild.locked (object builds, installing a derived model): a second holder of the folder's
    lock (here a thread with its own descriptor, as another process would have) waits for the
    first to let go."""
    import threading

    from levitron.runtime.model.cbuild import locked
    got = threading.Event()

    def second():
        with locked(tmp_path):
            got.set()

    with locked(tmp_path):
        t = threading.Thread(target=second)
        t.start()
        assert not got.wait(0.5)          # held: the second holder is still waiting
    assert got.wait(30)                   # released: it gets the lock
    t.join()


def test_another_models_stamped_library_is_rebuilt_not_blamed_on_the_folder(tmp_path, monkeypatch,
                                                                            capfd, seed_cache):
    """Another model's library with its own valid stamp copied onto this model's cache name: the
    table check refused it with "delete derived/<folder>", which could not help (the folder
    derives the same model.c, whose hash names the same wrong library). Now the library is
    rebuilt, once, with a note, and the model runs."""
    import shutil

    from levitron.scene.load import load_scene
    from levitron.runtime.model.load import load_model
    # seeded with the runtime/csrc objects only: both models' libraries are built here
    monkeypatch.setenv("LEVITRON_CACHE", str(seed_cache(tmp_path / "cache")))
    thesis = load_model(load_scene("thesis"))
    ours = thesis.library_path
    theirs = load_model(load_scene("square")).library_path
    assert ours != theirs and is_intact(ours) and is_intact(theirs)
    shutil.copyfile(theirs, ours)
    shutil.copyfile(f"{theirs}.sha256", f"{ours}.sha256")
    assert is_intact(ours)
    fresh = load_model(load_scene("thesis"))
    assert fresh.library_path == ours
    assert fresh.lib is not None
    assert "is not the one of" in capfd.readouterr().err
    assert is_intact(ours) and ours.read_bytes() != theirs.read_bytes()    # its table agreed


def test_a_model_library_exports_only_prefixed_symbols(thesis_model):
    """Every symbol a model's library defines begins `lev_` (no `field` or `onaxis` to meet another
    library's), and each generated function is the manifest's symbol_prefix + its name."""
    import shutil
    import subprocess
    if shutil.which("nm") is None:
        pytest.skip("binutils' nm is not installed")
    out = subprocess.run(["nm", "-D", "--defined-only", str(thesis_model.library_path)],
                         capture_output=True, text=True, check=True).stdout
    symbols = {line.split()[-1] for line in out.splitlines() if line.split()[1:2] == ["T"]}
    bare = sorted(s for s in symbols if not s.startswith("lev_"))
    assert symbols and bare == []
    prefix = thesis_model.manifest.symbol_prefix
    assert prefix == "lev_model_"
    assert {thesis_model.symbol(name) for name in thesis_model.manifest.functions} <= symbols
    assert f"{prefix}reduced_taylor" in symbols and f"{prefix}full_rhs_lanes" in symbols
