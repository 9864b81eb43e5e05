#!/usr/bin/env python3
"""Damages lcjit's cached object code in a cache folder: in place, the way a
disk, a full disk or an interrupted copy does. Usage: damage.py CACHE obj|sup MODE [--keep-checksum]
obj: objects/*.o; sup: the -O0 PCH's support code (*.pch.o). --keep-checksum rewrites the
checksum line over the damaged contents (an object that is whole on disk but will not load)."""
import glob, hashlib, os, sys

cache, what, mode = sys.argv[1], sys.argv[2], sys.argv[3]
keep = "--keep-checksum" in sys.argv
files = glob.glob(os.path.join(cache, "objects", "*.o")) if what == "obj" else glob.glob(os.path.join(cache, "*.pch.o"))
if not files:
    sys.exit("no cache files of kind " + what + " in " + cache)
for f in files:
    data = open(f, "rb").read()
    head, body = data.split(b"\n", 1) if keep else (b"", data)
    d = bytearray(body)
    elf = d.find(b"\x7fELF")
    if mode == "trunc_half":
        d = d[: len(d) // 2]
    elif mode == "zero_tail":
        d[len(d) // 2 :] = bytes(len(d) - len(d) // 2)
    elif mode == "flip_code":  # bytes just past the ELF header: the first section (.text)
        for i in range(elf + 0x40, elf + 0x40 + 48):
            d[i] ^= 0xFF
    elif mode == "elf_hdr":
        d[elf + 16] ^= 0xFF
        d[elf + 18] ^= 0xFF
    else:
        sys.exit("unknown mode " + mode)
    if keep:
        head = b"lcjit-sha256 " + hashlib.sha256(bytes(d)).hexdigest().encode()
        d = bytearray(head + b"\n") + d
    open(f, "wb").write(bytes(d))
