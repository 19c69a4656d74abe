"""Model bundles from files, like the C++ CLI's ReadModelBundle
(server/wire/model_bundle_files.cc)."""
import os
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


def read_model_bundle(urdf_path_or_dir: PathLike, scene: Optional[PathLike] = None,
                      assets: Iterable[PathLike] = (),
                      name: Optional[str] = None) -> "model_pb2.ModelBundle":
    """A ModelBundle from a URDF or SDFormat file (the server tells them apart by content),
    or from a directory holding exactly one .urdf, or else exactly one .sdf (then its one
    .scene, unless `scene` is given, and every .stl below it, named by their path relative
    to the directory). `assets` are more files, named by their file name."""
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
        stls = []
        for root, _, files in os.walk(path):
            stls += [os.path.join(root, f) for f in files if f.lower().endswith(".stl")]
        for stl in sorted(stls):
            _add_asset(bundle, os.path.relpath(stl, path).replace(os.sep, "/"), stl)
    bundle.urdf = _text(urdf_path)
    bundle.urdf_file_name = urdf_path
    if scene:
        bundle.scene_script = _text(os.fspath(scene))
    for asset in assets:
        asset = os.fspath(asset)
        _add_asset(bundle, os.path.basename(asset), asset)
    return bundle
