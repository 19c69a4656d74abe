"""Model bundles from files, like the C++ CLI's ReadModelBundle
(server/wire/model_bundle_files.cc)."""
import copy
import os
import posixpath
import re
import urllib.parse
import xml.etree.ElementTree as ET
from typing import Iterable, List, Optional, Sequence, Union

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


def _package_folders(package_path: Sequence[str], name: str) -> List[str]:
    """The folders below the package path entries (6 levels at most, in order) named `name`
    or whose package.xml names it, as the C++ model_files::PackageFolders finds them."""
    found = []
    for root in package_path:
        if not os.path.isdir(root):
            continue
        for folder, dirs, _ in os.walk(root):
            dirs[:] = sorted(d for d in dirs if not d.startswith("."))
            if folder[len(root):].count(os.sep) >= 6:
                dirs[:] = []
            xml = os.path.join(folder, "package.xml")
            named = False
            if os.path.isfile(xml):
                match = re.search(r"<name>\s*([^<\s]+)\s*</name>", _read(xml).decode("utf-8",
                                                                                    "replace"))
                named = bool(match and match.group(1) == name)
            if named or os.path.basename(folder) == name:
                found.append(folder)
    return found


def _include_file(uri: str, directory: str, package_path: Sequence[str]):
    """The model file an <include><uri> names, as the C++ FindSdfInclude finds it
    (shared/model_files/sdf_includes.h), and every place tried."""
    tried: List[str] = []

    def attempt(candidate: str) -> bool:
        candidate = os.path.normpath(candidate)
        if candidate not in tried:
            tried.append(candidate)
        return os.path.exists(candidate)

    if uri.startswith("file://"):
        return (uri[7:] if attempt(uri[7:]) else None), tried
    if not uri.startswith("model://"):
        candidate = uri if os.path.isabs(uri) else os.path.join(directory, uri)
        return (candidate if attempt(candidate) else None), tried
    name, _, rest = uri[len("model://"):].partition("/")
    folders = _package_folders(package_path, name)
    folder = os.path.abspath(directory)
    while True:
        folders.append(os.path.join(folder, name))
        if os.path.dirname(folder) == folder:
            break
        folder = os.path.dirname(folder)
    for folder in folders:
        if rest:
            if attempt(os.path.join(folder, rest)):
                return os.path.join(folder, rest), tried
            continue
        config = os.path.join(folder, "model.config")
        if attempt(config):
            sdf = ET.fromstring(_text(config)).findtext("sdf")
            return os.path.join(folder, (sdf or "model.sdf").strip()), tried
        if attempt(os.path.join(folder, "model.sdf")):
            return os.path.join(folder, "model.sdf"), tried
    return None, tried


def _line_of(text: str, needle: str) -> int:
    at = text.find(needle)
    return text.count("\n", 0, at) + 1 if at >= 0 else 0


def _expand_includes(element: ET.Element, text: str, source: str,
                     package_path: Sequence[str]) -> None:
    """Replaces each <include> below `element` by the <model> it names, with the include's
    <name>, <pose> and <static> (as libsdformat reads it, and as `mbstream submit` sends a
    world: the server reads no file a model names)."""
    for parent in list(element.iter()):
        for index, child in enumerate(list(parent)):
            if child.tag != "include":
                continue
            uri = (child.findtext("uri") or "").strip()
            where = "%s:%d" % (source, _line_of(text, uri)) if uri else source
            if child.find("placement_frame") is not None:
                raise bad_request("%s: <include> of '%s': <placement_frame> is not read by "
                                  "this client; give the <pose> of the model frame" % (where, uri))
            found, tried = _include_file(uri, os.path.dirname(source) or ".", package_path)
            if found is None or not os.path.isfile(found):
                raise bad_request(
                    "%s: <include> of '%s': not found; tried %s; give package_path=[DIR] (a "
                    "folder holding the model's folder, with its model.config or model.sdf) "
                    "or set MBSTREAM_PACKAGE_PATH" % (where, uri, ", ".join(tried)))
            included_text = _text(found)
            model = ET.fromstring(included_text).find("model")
            if model is None:
                raise bad_request("%s: <include> of '%s': %s holds no <model>; include a "
                                  "model" % (where, uri, found))
            model = copy.deepcopy(model)
            _expand_includes(model, included_text, found, package_path)
            include_name = (child.findtext("name") or "").strip()
            if include_name:
                model.set("name", include_name)
            for tag in ("pose", "static"):
                given = child.find(tag)
                if given is None:
                    continue
                for old in model.findall(tag):
                    model.remove(old)
                model.insert(0, copy.deepcopy(given))
            parent.remove(child)
            parent.insert(index, model)


def expand_sdf_includes(text: str, source: str,
                        package_path: Iterable[PathLike] = ()) -> str:
    """SDFormat `text` (read from `source`) with each <include> replaced by the model it
    names (found beside `source`, its ancestors and in `package_path`, then
    $MBSTREAM_PACKAGE_PATH); the text unchanged when it has none."""
    if "<include" not in text:
        return text
    paths = [os.fspath(p) for p in package_path]
    paths += [p for p in os.environ.get("MBSTREAM_PACKAGE_PATH", "").split(":") if p]
    root = ET.fromstring(text)
    _expand_includes(root, text, source, paths)
    return '<?xml version="1.0"?>\n' + ET.tostring(root, encoding="unicode") + "\n"


def read_model_bundle(urdf_path_or_dir: PathLike, scene: Optional[PathLike] = None,
                      assets: Iterable[PathLike] = (),
                      name: Optional[str] = None,
                      package_path: Iterable[PathLike] = ()) -> "model_pb2.ModelBundle":
    """A ModelBundle from a URDF or SDFormat file (the server tells them apart by content),
    or from a directory holding exactly one .urdf, or else exactly one .sdf (then its one
    .scene, unless `scene` is given, and every mesh file below it (.stl, .obj, .dae, .gltf,
    .glb), named by their path relative to the directory, with the files those name beside
    them: an OBJ's .mtl and its images, a Collada's or glTF's images and buffers, as
    `mbstream submit` attaches them). `assets` are more files, named by their file name. An
    SDFormat world's <include>s are read here and sent written into it (the server reads no
    file a model names): model://NAME is a folder NAME beside the file or an ancestor, or in
    `package_path` and $MBSTREAM_PACKAGE_PATH (docs/worlds.md)."""
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
    if re.search(r"<sdf[\s>]", bundle.urdf):
        try:
            bundle.urdf = expand_sdf_includes(bundle.urdf, urdf_path, package_path)
        except ET.ParseError as error:
            raise bad_request("%s: %s; fix the XML" % (urdf_path, error)) from None
    bundle.urdf_file_name = urdf_path
    if scene:
        bundle.scene_script = _text(os.fspath(scene))
    for asset in assets:
        asset = os.fspath(asset)
        _add_asset(bundle, os.path.basename(asset), asset)
    return bundle
