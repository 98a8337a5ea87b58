"""service.auth without a server: the keys file's format, lookups, reloading."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from service.auth import KeyFileError, KeyRing, hash_key, is_open, key_line, new_key, parse_keys


def test_key_line_round_trips_and_stores_the_sha256() -> None:
    import hashlib

    key = new_key()
    line = key_line("alice", key)
    assert line == f"alice sha256:{hashlib.sha256(key.encode()).hexdigest()}"
    assert parse_keys(line) == {hash_key(key): "alice"}
    assert new_key() != key


def test_comments_and_blank_lines_are_ignored() -> None:
    text = f"# team keys\n\n{key_line('a', 'k1')}  # laptop\n   \n{key_line('b.c-d_e', 'k2')}\n"
    assert parse_keys(text) == {hash_key("k1"): "a", hash_key("k2"): "b.c-d_e"}


@pytest.mark.parametrize("line", ["alice", "alice sha256:abc", "alice md5:" + "0" * 64,
                                  "al ice sha256:" + "0" * 64, "a/b sha256:" + "0" * 64])
def test_malformed_lines_name_their_number(line: str) -> None:
    with pytest.raises(KeyFileError, match=r"keys, line 2: expected 'NAME sha256:HEX'"):
        parse_keys("# ok\n" + line, "keys")


def test_bad_names_are_refused() -> None:
    with pytest.raises(KeyFileError, match="1-64 letters"):
        key_line("x" * 65, "k")
    with pytest.raises(KeyFileError, match="1-64 letters"):
        key_line("a\x1fb", "k")  # the separator of scoped idempotency keys


def test_keyring_finds_owners_and_rereads_a_changed_file(tmp_path: Path) -> None:
    path = tmp_path / "keys"
    path.write_text(key_line("alice", "k1") + "\n")
    ring = KeyRing(path)
    assert ring.owner("k1") == "alice" and ring.owner("k2") is None and len(ring) == 1
    path.write_text(key_line("alice", "k1") + "\n" + key_line("bob", "k2") + "\n")
    os.utime(path, ns=(1, 1))  # a different stamp even on coarse-clock file systems
    assert ring.owner("k2") == "bob"
    path.write_text("garbage\n")
    os.utime(path, ns=(2, 2))
    assert ring.owner("k2") == "bob"  # an unreadable update keeps the previous keys


def test_keyring_refuses_a_missing_or_broken_file_at_start(tmp_path: Path) -> None:
    with pytest.raises(KeyFileError, match="Cannot use the API keys file"):
        KeyRing(tmp_path / "absent")
    (tmp_path / "bad").write_text("x y\n")
    with pytest.raises(KeyFileError, match="line 1"):
        KeyRing(tmp_path / "bad")


@pytest.mark.parametrize(("path", "open_"), [
    ("/healthz", True), ("/openapi.json", True), ("/ui", True), ("/ui/vendor/three/x.js", True),
    ("/docs", True), ("/docs/assets/swagger-ui.css", True), ("/uix", False),
    ("/docsx/a", False), ("/jobs", False), ("/processes/ui", False), ("/", False),
])
def test_only_probes_the_description_and_static_trees_are_open(path: str, open_: bool) -> None:
    assert is_open(path) is open_
