"""Model bundles from files, like the C++ CLI's ReadModelBundle
(server/wire/model_bundle_files.cc)."""
import os
import posixpath
import re
import urllib.parse
from typing import Iterable, Optional, Union

from ._stubs import model_pb2
from .errors import bad_request


PathLike = Union[str, "os.PathLike[str]"]


def _read(path: str) -> bytes:
    try:
        with open(path, "rb") as f:
            return f.read()
    except OSError:
        raise bad_request("cannot read %s: check the path and permissions" % path) from None


def _text(path: str) -> str:
    """A text file of the bundle as str: protobuf strings hold UTF-8 only, so anything else
    is named here by file and line (as the C++ CLI does), not as a UnicodeDecodeError."""
    data = _read(path)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        line = data.count(b"\n", 0, error.start) + 1
        what = ("the file is UTF-16 or UTF-32, not UTF-8" if b"\0" in data else
                "byte 0x%02X is not UTF-8" % data[error.start])
        raise bad_request("%s: line %d: %s; convert the file to UTF-8 (e.g. iconv -f latin1 "
                          "-t utf-8)" % (path, line, what)) from None


def _files_with_extension(directory: str, ext: str) -> list:
    return sorted(os.path.join(directory, n) for n in os.listdir(directory)
                  if n.lower().endswith(ext) and os.path.isfile(os.path.join(directory, n)))


def _add_asset(bundle: "model_pb2.ModelBundle", name: str, path: str) -> None:
    if any(a.name == name for a in bundle.assets):
        raise bad_request("asset '%s' (%s) is given twice; rename one of "
                            "the files" % (name, path))
    bundle.assets.add(name=name, data=_read(path))


_MESHES = (".stl", ".obj", ".dae", ".gltf", ".glb")


def _references(name: str, data: bytes) -> list:
    """The files a mesh or material file names, as the C++ MeshFileReferences
    (server/parse/mesh_dependencies.cc): an OBJ's mtllib, an MTL's map_*/bump/disp/decal/refl/
    norm images (the last word), a Collada's <library_images> <init_from>, a glTF's "uri"s;
    embedded data and URLs are not references."""
    text = data.decode("utf-8", "replace")
    lower = name.lower()
    found = []
    if lower.endswith(".obj"):
        found = [line.split(None, 1)[1] for line in text.splitlines()
                 if line.strip().startswith("mtllib") and len(line.split(None, 1)) == 2
                 and line.split(None, 1)[0] == "mtllib"]
    elif lower.endswith(".mtl"):
        for line in text.splitlines():
            words = line.split()
            key = words[0].lower() if words else ""
            if len(words) > 1 and ((key.startswith("map_") and len(key) > 4) or
                                   key in ("bump", "disp", "decal", "refl", "norm")):
                found.append(words[-1])
    elif lower.endswith(".dae"):
        for images in re.findall(r"<library_images.*?(?:</library_images|$)", text, re.S):
            found += [re.sub(r"^<ref>(.*)</ref>$", r"\1", v.strip())
                      for v in re.findall(r"<init_from>(.*?)</init_from>", images, re.S)]
    elif lower.endswith(".gltf"):
        found = [u.replace("\\/", "/") for u in re.findall(r'"uri"\s*:\s*"([^"]*)"', text)]
    names = []
    for ref in found:
        ref = ref.strip()
        if ref.startswith("file://"):
            ref = ref[7:]
        if not ref or ref.startswith("data:") or "://" in ref:
            continue
        ref = urllib.parse.unquote(ref).replace("\\", "/")
        if ref not in names:
            names.append(ref)
    return names


def _add_referenced(bundle: "model_pb2.ModelBundle", name: str, path: str) -> None:
    """Attaches the files the mesh `path` (asset `name`) names beside it, as the C++ CLI does:
    relative to the mesh, else by file name beside it; never outside the bundle."""
    for ref in _references(name, _read(path)):
        folder = posixpath.dirname(name)
        for candidate in (ref, posixpath.basename(ref)):
            if candidate.startswith("/") or re.match(r"^[A-Za-z]:", candidate):
                continue
            asset = posixpath.normpath(posixpath.join(folder, candidate))
            file = os.path.join(os.path.dirname(path), candidate)
            if asset.startswith("..") or not os.path.isfile(file):
                continue
            if not any(a.name == asset for a in bundle.assets):
                _add_asset(bundle, asset, file)
                _add_referenced(bundle, asset, file)
            break


def read_model_bundle(urdf_path_or_dir: PathLike, scene: Optional[PathLike] = None,
                      assets: Iterable[PathLike] = (),
                      name: Optional[str] = None) -> "model_pb2.ModelBundle":
    """A ModelBundle from a URDF or SDFormat file (the server tells them apart by content),
    or from a directory holding exactly one .urdf, or else exactly one .sdf (then its one
    .scene, unless `scene` is given, and every mesh file below it (.stl, .obj, .dae, .gltf,
    .glb), named by their path relative to the directory, with the files those name beside
    them: an OBJ's .mtl and its images, a Collada's or glTF's images and buffers, as
    `mbstream submit` attaches them). `assets` are more files, named by their file name."""
    path = os.fspath(urdf_path_or_dir)
    bundle = model_pb2.ModelBundle(name=name or "")
    urdf_path = path
    if os.path.isdir(path):
        urdfs = _files_with_extension(path, ".urdf")
        if not urdfs:
            urdfs = _files_with_extension(path, ".sdf")
        if len(urdfs) != 1:
            raise bad_request(
                "%s: a model directory needs exactly one .urdf file (or, without one, "
                "exactly one .sdf file), found %d; name the model file instead"
                % (path, len(urdfs)))
        urdf_path = urdfs[0]
        scenes = _files_with_extension(path, ".scene")
        if len(scenes) == 1 and not scene:
            bundle.scene_script = _text(scenes[0])
        meshes = []
        for root, _, files in os.walk(path):
            meshes += [os.path.join(root, f) for f in files if f.lower().endswith(_MESHES)]
        for mesh in sorted(meshes):
            name_in_bundle = os.path.relpath(mesh, path).replace(os.sep, "/")
            if not any(a.name == name_in_bundle for a in bundle.assets):
                _add_asset(bundle, name_in_bundle, mesh)
                _add_referenced(bundle, name_in_bundle, mesh)
    bundle.urdf = _text(urdf_path)
    bundle.urdf_file_name = urdf_path
    if scene:
        bundle.scene_script = _text(os.fspath(scene))
    for asset in assets:
        asset = os.fspath(asset)
        _add_asset(bundle, os.path.basename(asset), asset)
    return bundle
