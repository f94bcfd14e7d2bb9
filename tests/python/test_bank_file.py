"""core.ModelBank and the bank file: round trip, hash = hashlib's SHA-256 of the payload,
deterministic bytes, an independent decode with the generated Python LCM type, and
refusal of every kind of bad bank or file with a message naming the problem."""
from __future__ import annotations

import hashlib
import importlib
import pickle
import struct
from types import SimpleNamespace

import numpy as np
import pytest
import scipy.linalg

import f16mmae
from f16mmae import core, names
from f16mmae.bench import estimator as bench

HEADER = struct.Struct(">8sIQ32s")  # magic, format version, payload size, SHA-256 (52 bytes)


def random_models(n_hyp=3, nx=4, nu=2, nz=3, seed=0):
    """Small random stable systems with DARE steady-state gains: (name, dict) pairs."""
    rng = np.random.default_rng(seed)
    models = []
    for i in range(n_hyp):
        phi = rng.standard_normal((nx, nx))
        phi *= 0.9 / np.max(np.abs(np.linalg.eigvals(phi)))
        bd, h = rng.standard_normal((nx, nu)), rng.standard_normal((nz, nx))
        r = 0.01 * np.eye(nz)
        p = scipy.linalg.solve_discrete_are(phi.T, h.T, 0.1 * np.eye(nx), r)
        a = h @ p @ h.T + r
        a = 0.5 * (a + a.T)
        k = p @ h.T @ np.linalg.inv(a)
        models.append(("NONE" if i == 0 else f"H{i}", dict(phi=phi, bd=bd, h=h, k=k, a=a)))
    return models


def make_bank(models=None, nx=4, nu=2, nz=3, **overrides):
    models = random_models(nx=nx, nu=nu, nz=nz) if models is None else models
    kwargs = dict(
        state_names=[f"x{i}" for i in range(nx)],
        input_names=[f"u{i}" for i in range(nu)],
        measurement_names=[f"z{i}" for i in range(nz)],
        frame_rate_hz=64.0,
        u_trim=np.linspace(-0.1, 0.1, nu),
        z_trim=np.linspace(1.0, 400.0, nz),
        mach=0.4,
        alt_ft=20000.0,
        tuning="untuned",
        metadata={"generator": "test_bank_file", "seed": 0},
    )
    kwargs.update(overrides)
    return core.ModelBank(models, **kwargs)


@pytest.fixture(scope="module")
def lcmt_model_bank():
    """The Python LCM type generated from lcm_types/lcmt_model_bank.lcm. lcm-gen's Python
    code finds nested types as attributes of the package (its own generated __init__.py
    imports them); f16mmae's __init__.py is ours, so bind them here if it does not."""
    for name in ("lcmt_bank_matrix", "lcmt_bank_hypothesis", "lcmt_model_bank"):
        if not isinstance(getattr(f16mmae, name, None), type):
            setattr(f16mmae, name, getattr(importlib.import_module(f"f16mmae.{name}"), name))
    return f16mmae.lcmt_model_bank


def image(payload: bytes, version: int = core.ModelBank.FORMAT_VERSION) -> bytes:
    """A file image built here from the documented layout."""
    return HEADER.pack(b"F16MMAEB", version, len(payload), hashlib.sha256(payload).digest()) + payload


def assert_banks_equal(a, b):
    assert a.hypothesis_names == b.hypothesis_names
    for name in ("state_names", "input_names", "measurement_names", "frame_rate_hz", "mach", "alt_ft",
                 "tuning", "p_min", "threshold", "dwell_s", "metadata", "content_hash"):
        assert getattr(a, name) == getattr(b, name), name
    for name in ("u_trim", "z_trim", "h_output"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    for ha, hb in zip(a.hypotheses, b.hypotheses):
        for m in ("phi", "bd", "h", "k", "a"):
            np.testing.assert_array_equal(getattr(ha, m), getattr(hb, m))


def test_round_trip_and_hash_is_sha256_of_payload(tmp_path):
    bank = make_bank()
    path = tmp_path / "small.bank"
    assert bank.save(path) == bank.content_hash
    loaded = core.load_bank(path)
    assert_banks_equal(bank, loaded)
    data = path.read_bytes()
    magic, version, size, digest = HEADER.unpack_from(data)
    payload = data[HEADER.size:]
    assert (magic, version, size) == (b"F16MMAEB", core.ModelBank.FORMAT_VERSION, len(payload))
    assert digest == hashlib.sha256(payload).digest()
    assert bank.content_hash == hashlib.sha256(payload).hexdigest()
    assert bank.to_bytes() == data
    assert core.ModelBank.from_bytes(data) == bank


def test_payload_decodes_with_the_python_lcm_type(lcmt_model_bank):
    bank = make_bank()
    payload = bank.to_bytes()[HEADER.size:]
    msg = lcmt_model_bank.decode(payload)
    assert msg.encode() == payload  # Python and C++ LCM encodings agree byte for byte
    assert [h.name for h in msg.hypotheses] == list(bank.hypothesis_names)
    np.testing.assert_array_equal(np.array(msg.hypotheses[1].k.data), bank["H1"].k)
    np.testing.assert_array_equal(msg.z_trim, bank.z_trim)
    assert (msg.mach, msg.alt_ft, msg.tuning) == (0.4, 20000.0, "untuned")


def test_same_bank_same_bytes_and_one_ulp_changes_the_hash(tmp_path):
    assert make_bank().to_bytes() == make_bank().to_bytes()
    make_bank().save(tmp_path / "a.bank")
    make_bank().save(tmp_path / "b.bank")
    assert (tmp_path / "a.bank").read_bytes() == (tmp_path / "b.bank").read_bytes()
    models = random_models()
    models[1][1]["k"][0, 0] = np.nextafter(models[1][1]["k"][0, 0], np.inf)
    assert make_bank(models).content_hash != make_bank().content_hash
    assert make_bank(metadata={"seed": 0, "generator": "test_bank_file"}) == make_bank()  # canonical JSON


def test_f16_sized_bank_of_79_hypotheses(tmp_path):
    bank = bench.synthetic_bank(names.ALL_HYPOTHESES)
    assert len(bank) == 79 and (bank.nx, bank.nu, bank.nz) == (13, 5, 7)
    path = tmp_path / "f16.bank"
    bank.save(path)
    loaded = core.load_bank(path)
    assert_banks_equal(bank, loaded)
    doubles = 79 * (13 * 13 + 13 * 5 + 7 * 13 + 13 * 7 + 7 * 7) + 7 * 13 + 5 + 7
    assert doubles * 8 < path.stat().st_size < doubles * 8 + 8192
    np.testing.assert_array_equal(loaded["LS+PIT"].bd[:, 0], 0.0)  # failed actuator's column
    np.testing.assert_array_equal(loaded["LS+PIT"].h[2], 0.0)  # failed sensor's row


def test_construction_forms_lookup_and_immutability():
    models = random_models()
    by_pairs = make_bank(models)
    typed = [core.HypothesisModel(name=n, **m) for n, m in models]
    assert make_bank(typed) == by_pairs
    assert make_bank(dict(models)) == by_pairs
    assert make_bank([(n, SimpleNamespace(**m)) for n, m in models]) == by_pairs  # FilterModel-like
    assert len(by_pairs) == 3 and "H2" in by_pairs and "LS" not in by_pairs
    assert by_pairs.index("H2") == 2 and by_pairs[-1].name == "H2" and by_pairs[0].name == "NONE"
    np.testing.assert_array_equal(by_pairs["H1"].phi, models[1][1]["phi"])
    np.testing.assert_array_equal(by_pairs.h_output, models[0][1]["h"])  # default: the unfailed H
    with pytest.raises(KeyError, match="no hypothesis 'LS'.*NONE, H1, H2"):
        by_pairs["LS"]
    with pytest.raises(IndexError):
        by_pairs[3]
    with pytest.raises(ValueError, match="read-only"):
        by_pairs.u_trim[0] = 1.0
    with pytest.raises(AttributeError):
        by_pairs.mach = 0.5
    assert pickle.loads(pickle.dumps(by_pairs)) == by_pairs


@pytest.mark.parametrize(
    "spoil, message",
    [
        (lambda m: m[1][1].update(phi=m[1][1]["phi"][:, :3]), r"'H1': phi is 4x3, expected 4x4"),
        (lambda m: m[2][1].update(a=-m[2][1]["a"]), r"'H2': residual covariance A is not positive definite"),
        (lambda m: m[0][1].update(phi=50 * m[0][1]["phi"]), r"'NONE': error dynamics Phi \(I - K H\) is unstable"),
        (lambda m: m[1][1]["k"].__setitem__((0, 0), np.nan), r"'H1': k has a non-finite entry"),
        (lambda m: m.__setitem__(0, ("LS", m[0][1])), "hypothesis 0 must be NONE"),
    ],
)
def test_bad_banks_are_refused_by_name(tmp_path, spoil, message):
    models = random_models()
    spoil(models)
    with pytest.raises(ValueError, match=message):
        make_bank(models)
    unchecked = make_bank(models, validate=False)
    with pytest.raises(ValueError, match=message):
        unchecked.validate()
    with pytest.raises(ValueError, match=message):
        unchecked.save(tmp_path / "bad.bank")
    assert list(tmp_path.iterdir()) == []  # nothing written, not even a temporary file
    # the same content in a well-formed, correctly hashed file is refused on load
    path = tmp_path / "crafted.bank"
    path.write_bytes(image(unchecked.__getstate__()))  # the LCM payload
    with pytest.raises(ValueError, match=message):
        core.load_bank(path)


def test_boundary_errors_name_the_argument():
    n, m = random_models()[0]
    with pytest.raises(ValueError, match=r"'NONE': phi must be a 2-D array, got shape \(4,\)"):
        core.HypothesisModel(name=n, **{**m, "phi": np.ones(4)})
    with pytest.raises(ValueError, match="bd must be an array of real numbers, got dtype <U3"):
        core.HypothesisModel(name=n, **{**m, "bd": "abc"})
    with pytest.raises(ValueError, match="k must be an array of real numbers, got dtype complex128"):
        core.HypothesisModel(name=n, **{**m, "k": m["k"] + 1j})
    with pytest.raises(ValueError, match="the model has no 'a'"):
        make_bank([(n, {k: v for k, v in m.items() if k != "a"})])
    with pytest.raises(ValueError, match=r"u_trim has size 3, expected 2"):
        make_bank(u_trim=np.zeros(3))
    with pytest.raises(ValueError, match="state_names must be a sequence of str"):
        make_bank(state_names="x0x1x2x3")
    with pytest.raises(ValueError, match=r"hypotheses\[0\] must be a core.HypothesisModel or a \(name, model\) pair"):
        make_bank([m])


def test_bad_files_are_refused_with_the_reason(tmp_path, lcmt_model_bank):
    good = make_bank().to_bytes()
    payload = good[HEADER.size:]
    path = tmp_path / "bad.bank"

    def refused(data: bytes, message: str, error=ValueError):
        path.write_bytes(data)
        with pytest.raises(error, match=message) as info:
            core.load_bank(path)
        assert str(path) in str(info.value)

    refused(b"", "truncated: the file is empty")
    refused(good[:30], "truncated")
    refused(good[:-1], f"truncated: the payload has {len(payload) - 1} bytes, the header declares {len(payload)}")
    refused(good + b"\0", "1 unexpected bytes after")
    flipped = bytearray(good)
    flipped[len(good) // 2] ^= 0x01
    refused(bytes(flipped), "content hash mismatch, the file is corrupted")
    refused(b"PK\x03\x04" + good[4:], r"wrong magic bytes 'PK\\x03\\x04MAEB'")
    refused(image(payload, version=5), "unsupported format version 5 .this build reads version 4")
    for old in (1, 2, 3):
        refused(image(payload, version=old), f"format version {old} is no longer read: this build reads version 4, "
                "where the estimator settings are typed fields and each hypothesis carries the widths of its "
                r"uninformative channels and its recommended evidence dwell \(dwell_nats\). Regenerate the bank "
                r"with the design command .*\(the shipped banks: `python -m f16mmae.design.calibrate --banks`\)")
    refused(image(b"\x01" + payload[1:]), "fingerprint")
    refused(image(payload[:-21]), r"payload field hypotheses\[2\]\.a \(byte \d+\) is 3x3, 72 bytes, but 63 remain")
    # a wrong shape, written by the independent Python LCM encoder
    msg = lcmt_model_bank.decode(payload)
    msg.hypotheses[2].a.rows, msg.hypotheses[2].a.data = 2, msg.hypotheses[2].a.data[:2]
    refused(image(msg.encode()), r"'H2': a is 2x3, expected 3x3")
    with pytest.raises(FileNotFoundError, match="no such file"):
        core.load_bank(tmp_path / "absent.bank")
    with pytest.raises(OSError, match="is a directory"):
        core.load_bank(tmp_path)
    with pytest.raises(OSError, match="cannot create a temporary file"):
        make_bank().save(tmp_path / "no" / "such" / "folder.bank")
