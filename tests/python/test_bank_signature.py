"""Optional Ed25519 bank signatures (cpp/bankfile/bank_signature.h): the RFC 8032 test vector,
a signed bank loads, a substituted or changed bank, a missing signature, another key and
malformed key files are refused by name, in Python and by mmae-daemon --bank-public-key."""
from __future__ import annotations

import shutil
import subprocess

import pytest

from f16mmae import core
from f16mmae.design import bank as design_bank
from f16mmae.lcm.daemon import find_executable

# RFC 8032, section 7.1, TEST 1: the empty message
RFC_SEED = bytes.fromhex("9d61b19deffd5a60ba844af492ec2cc44449c5697b326919703bac031cae7f60")
RFC_PUBLIC = bytes.fromhex("d75a980182b10ab7d54bfed3c964073a0ee172f3daa62325af021a68f707511a")
RFC_SIGNATURE = bytes.fromhex("e5564300c360ac729086e2cc806e828a84877f1eb8e5d974d873e065224901555fb8821590a33bac"
                              "c61e39701cf9b46bd25bf5f0595bbe24655141438e7a100b")


def test_signing_matches_the_rfc_8032_test_vector(tmp_path):
    empty = tmp_path / "empty"
    empty.write_bytes(b"")
    (tmp_path / "sk").write_bytes(RFC_SEED + RFC_PUBLIC)  # libsodium's secret key: seed, public key
    core.sign_bank_file(empty, tmp_path / "sk")
    assert (tmp_path / "empty.sig").read_bytes() == RFC_SIGNATURE


@pytest.fixture()
def signed(tmp_path):
    bank = tmp_path / "tuned.f16bank"
    shutil.copy(design_bank.nominal_bank_path("tuned"), bank)
    core.generate_bank_signing_keys(tmp_path / "pk", tmp_path / "sk")
    assert (tmp_path / "pk").stat().st_size == 32 and (tmp_path / "sk").stat().st_size == 64
    assert (tmp_path / "sk").stat().st_mode & 0o777 == 0o600
    core.sign_bank_file(bank, tmp_path / "sk")
    return bank, tmp_path / "pk"


def test_a_signed_bank_loads_and_is_the_same_bank(signed):
    bank, pk = signed
    assert core.load_bank(bank, public_key=pk) == core.load_bank(bank)


def test_substitution_changes_missing_signature_and_other_keys_are_refused(signed, tmp_path):
    bank, pk = signed
    sig = bank.with_name(bank.name + ".sig")
    good_sig = sig.read_bytes()
    # another valid, correctly hashed bank in its place: the hash cannot tell, the signature can
    shutil.copy(design_bank.nominal_bank_path("untuned"), bank)
    core.load_bank(bank)
    with pytest.raises(ValueError, match=f"its signature '{sig}' does not verify with the public key '{pk}'"):
        core.load_bank(bank, public_key=pk)
    shutil.copy(design_bank.nominal_bank_path("tuned"), bank)
    core.load_bank(bank, public_key=pk)
    core.generate_bank_signing_keys(tmp_path / "pk2", tmp_path / "sk2")
    with pytest.raises(ValueError, match="does not verify"):
        core.load_bank(bank, public_key=tmp_path / "pk2")
    sig.write_bytes(good_sig[:-1] + bytes([good_sig[-1] ^ 1]))
    with pytest.raises(ValueError, match="does not verify"):
        core.load_bank(bank, public_key=pk)
    sig.write_bytes(good_sig[:40])
    with pytest.raises(ValueError, match=f"bank signature '{sig}': is 40 bytes, over|is 40 bytes, expected 64"):
        core.load_bank(bank, public_key=pk)
    sig.unlink()
    with pytest.raises(ValueError, match="no signature .* and a public key was given: the bank must be signed"):
        core.load_bank(bank, public_key=pk)
    (tmp_path / "short.pk").write_bytes(b"\0" * 31)
    with pytest.raises(ValueError, match="public key '.*short.pk': is 31 bytes, expected 32"):
        core.load_bank(bank, public_key=tmp_path / "short.pk")


def test_the_daemon_refuses_a_bank_whose_signature_does_not_verify(signed):
    bank, pk = signed
    shutil.copy(design_bank.nominal_bank_path("untuned"), bank)
    proc = subprocess.run([str(find_executable("mmae-daemon")), "--bank", str(bank), "--bank-public-key", str(pk),
                           "--lcm-url", "memq://", "--max-frames", "1", "--quiet"],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 1
    assert "does not verify with the public key" in proc.stderr and str(bank) in proc.stderr
