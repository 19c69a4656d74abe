"""Run specs: the RunSpec message from a dict, a JSON file or JSON text, plus overrides."""
import json
import os
from typing import Any, Dict, Union

from google.protobuf import json_format
from google.protobuf.descriptor import FieldDescriptor

from ._stubs import run_spec_pb2
from .errors import bad_request

# The C++ CLI's override flags (`mbstream run --duration ...`) and the RunSpec fields they set.
OVERRIDE_ALIASES = {
    "duration": "duration_s",
    "output_interval": "output_interval_s",
    "max_step": "max_step_s",
    "step": "fixed_step_s",
}


SpecLike = Union[None, "run_spec_pb2.RunSpec", Dict[str, Any], str, "os.PathLike[str]"]


def _parse(value: Any, where: str) -> "run_spec_pb2.RunSpec":
    try:
        return json_format.ParseDict(value, run_spec_pb2.RunSpec())
    except json_format.ParseError as error:
        raise bad_request("%s: %s" % (where, error)) from None


_NUMBER_TYPES = {
    FieldDescriptor.CPPTYPE_DOUBLE, FieldDescriptor.CPPTYPE_FLOAT, FieldDescriptor.CPPTYPE_INT32,
    FieldDescriptor.CPPTYPE_INT64, FieldDescriptor.CPPTYPE_UINT32, FieldDescriptor.CPPTYPE_UINT64,
}


def _check_scalar(field: FieldDescriptor, key: str, value: Any) -> None:
    """An override of a number field must be a number, of a bool field a bool, of a string
    field a str: protobuf's JSON mapping would read duration="5" as 5 without a word."""
    if field.label == FieldDescriptor.LABEL_REPEATED:
        return
    if field.cpp_type in _NUMBER_TYPES:
        ok = isinstance(value, (int, float)) and not isinstance(value, bool)
        expected = "a number"
    elif field.cpp_type == FieldDescriptor.CPPTYPE_BOOL:
        ok, expected = isinstance(value, bool), "True or False"
    elif field.cpp_type == FieldDescriptor.CPPTYPE_STRING:
        ok, expected = isinstance(value, str), "a str"
    else:
        return
    if not ok:
        raise TypeError("override %s=%r: %s must be %s, not %s"
                        % (key, value, field.name, expected, type(value).__name__))


def load_spec(spec: SpecLike = None, **overrides: Any) -> "run_spec_pb2.RunSpec":
    """A RunSpec from `spec` — None (every field absent: the server's defaults), a RunSpec,
    a dict in protobuf's JSON mapping (field names like "duration_s" or "durationS"), a path
    to a JSON file (e.g. models/irb1600/seed-run.json) or JSON text — with `overrides` applied:
    any RunSpec field by name (rtol=1e-8, drives=[...], gravity={"z": -9.81}) or the CLI's
    names duration, output_interval, max_step, step. A repeated field is replaced, not
    extended."""
    if spec is None:
        result = run_spec_pb2.RunSpec()
    elif isinstance(spec, run_spec_pb2.RunSpec):
        result = run_spec_pb2.RunSpec()
        result.CopyFrom(spec)
    elif isinstance(spec, dict):
        result = _parse(spec, "run spec")
    elif isinstance(spec, (str, os.PathLike)):
        text = os.fspath(spec)
        if text.lstrip().startswith("{"):
            where, source = "run spec", text
        else:
            where = text
            try:
                with open(text, encoding="utf-8") as f:
                    source = f.read()
            except OSError:
                raise bad_request("cannot read run spec %s: check the path" % text) from None
        try:
            value = json.loads(source)
        except ValueError as error:
            raise bad_request("%s: not JSON: %s" % (where, error)) from None
        result = _parse(value, where)
    else:
        raise TypeError("spec must be None, a RunSpec, a dict or a JSON path, not %s"
                        % type(spec).__name__)
    fields = run_spec_pb2.RunSpec.DESCRIPTOR.fields_by_name
    for key, value in overrides.items():
        if value is None:
            continue
        field = OVERRIDE_ALIASES.get(key, key)
        if field not in fields:
            raise TypeError("unknown run spec override '%s'; use a RunSpec field (%s) or one of %s"
                            % (key, ", ".join(sorted(fields)), ", ".join(OVERRIDE_ALIASES)))
        _check_scalar(fields[field], key, value)
        if hasattr(value, "DESCRIPTOR"):  # a message (Vector3, Baumgarte)
            value = json_format.MessageToDict(value, preserving_proto_field_name=True)
        elif isinstance(value, (list, tuple)):
            value = [json_format.MessageToDict(v, preserving_proto_field_name=True)
                     if hasattr(v, "DESCRIPTOR") else v for v in value]
        update = _parse({field: value}, "override %s=%r" % (key, value))
        result.ClearField(field)
        result.MergeFrom(update)
    return result


def spec_to_dict(spec: "run_spec_pb2.RunSpec") -> Dict[str, Any]:
    """A RunSpec as a dict of its present fields (protobuf's JSON mapping, proto names)."""
    return json_format.MessageToDict(spec, preserving_proto_field_name=True)
