"""nodetrace.open(): headers, trailers and records equal what tracetool reads."""
import json
import struct

import numpy as np
import pytest

import nodetrace
from conftest import run

KINDS = "rwimcv"


def tracetool_records(path, *options):
    """The records as `tracetool cat` prints them (din: size 4, as Dinero IV reads din)."""
    rows = []
    for line in run("tracetool", "cat", *options, path).stdout.splitlines():
        fields = line.split()
        if fields[0].isdigit():  # din: LABEL ADDRESS [TAG [UNIT]]
            rows.append((int(fields[1], 16), 4, int(fields[0]), fields[2] if len(fields) > 2 else ""))
        else:  # xdin: TYPE ADDRESS SIZE [TAG [UNIT]]
            rows.append((int(fields[1], 16), int(fields[2], 16), KINDS.index(fields[0]),
                         fields[3] if len(fields) > 3 else ""))
    return rows


def as_rows(records):
    def tag(level):
        if level == nodetrace.TAG_NONE:
            return ""
        return {nodetrace.TAG_PRIMITIVE_LIST: "p", nodetrace.TAG_TRIANGLE: "t"}.get(level, "%02d" % level)
    return [(int(r["address"]), int(r["size"]), int(r["kind"]), tag(int(r["level"]))) for r in records]


def skippable_json(data, offset):
    size = struct.unpack_from("<I", data, offset + 4)[0]
    return json.loads(data[offset + 8:offset + 8 + size])


def test_whole_read_of_a_plain_trace_grows_its_array_without_losing_records(traces):
    # A plain trace says nothing of its length: records() maps 4096 records
    # and grows the mapping in place (mremap) as the records come.
    container = nodetrace.open(str(traces["container"])).records()
    plain = nodetrace.open(str(traces["plain_zstd"]), tags_are_levels=True).records()
    assert len(plain) > 8 * 4096
    assert np.array_equal(plain, container)


def test_container_header_and_trailer_are_the_files_json(traces):
    data = traces["container"].read_bytes()
    trace = nodetrace.open(str(traces["container"]))
    assert trace.header == skippable_json(data, 0)
    json_size = struct.unpack_from("<I", data, len(data) - 12)[0]
    start = len(data) - 20 - json_size
    assert trace.trailer == json.loads(data[start:start + json_size])
    assert trace.input_kind == "container" and trace.form == "din" and trace.tags_are_levels


@pytest.mark.parametrize("form", ["container", "xdin_container", "din", "xdin", "binary", "plain_zstd"])
def test_records_equal_tracetool_cat(traces, form):
    path = str(traces[form])
    levels = [] if form in ("container", "xdin_container", "binary") else ["--tags-are-levels"]
    trace = nodetrace.open(path, tags_are_levels=bool(levels))
    records = trace.records()
    assert records.dtype == nodetrace.RECORD_DTYPE
    as_text = ["--records", "xdin"] if form == "binary" else []
    assert as_rows(records) == tracetool_records(path, *levels, *as_text)
    assert len(records) > 1000


def test_plain_traces_have_no_header_or_trailer(traces):
    trace = nodetrace.open(str(traces["din"]))
    assert trace.header is None and trace.trailer is None and trace.input_kind == "plain"
    # Untagged without tags_are_levels, as tracetool reads it.
    assert set(trace.records()["level"]) == {nodetrace.TAG_NONE}


def test_informat_names_the_form_of_plain_input(traces):
    records = nodetrace.open(str(traces["xdin"]), informat="xdin", tags_are_levels=True).records()
    assert as_rows(records) == tracetool_records(traces["xdin"], "--tags-are-levels", "--informat", "xdin")


def test_batches_are_the_records_in_order(traces):
    trace = nodetrace.open(str(traces["container"]))
    whole = trace.records()
    batches = list(trace.batches(1000))
    assert [len(b) for b in batches[:-1]] == [1000] * (len(batches) - 1)
    assert 0 < len(batches[-1]) <= 1000
    assert np.array_equal(np.concatenate(batches), whole)


def test_frame_is_the_animation_frame_of_each_record(tmp_path, kitchen):
    path = tmp_path / "frames.din.zst"
    run("tracer", "render", kitchen, "--width", 8, "--height", 6, "--frames", "0-2", "-q", "-o", path)
    trace = nodetrace.open(str(path))
    records = trace.records()
    assert len(records) == len(tracetool_records(path))
    assert list(np.unique(records["frame"])) == [0, 1, 2]
    # Each data frame's records belong to the animation frame the trailer's index gives it.
    for first, count, frame in [(row[2], row[3], row[4]) for row in trace.trailer["index"]]:
        assert set(records["frame"][first:first + count]) == {frame}


def test_units_are_read_from_a_trace_of_several_units(tmp_path):
    path = tmp_path / "units.din.zst"
    run("tracer", "render", "sphereflake:1", "--width", 8, "--height", 6, "--units", 2, "--unit-pixels", 4, "-q",
        "-o", path)
    records = nodetrace.open(str(path)).records()
    units = [int(line.split()[3]) for line in run("tracetool", "cat", path).stdout.splitlines()]
    assert list(records["unit"]) == units and set(units) == {0, 1}


def tracetool_error(path):
    """What `tracetool cat` says of a bad trace (exit 1), without its program name."""
    program = run("tracetool", "cat", path, check=False)
    assert program.returncode == 1
    return program.stderr.strip().splitlines()[-1].removeprefix("tracetool cat: ")


@pytest.mark.parametrize("where", ["data frame", "marker"])
def test_damaged_trace_raises_format_error_with_the_readers_message(traces, tmp_path, where):
    data = bytearray(traces["container"].read_bytes())
    index = nodetrace.open(str(traces["container"])).trailer["index"]
    header_size = struct.unpack_from("<I", data, 4)[0] + 8
    offset = index[0][0] + 100 if where == "data frame" else header_size + 40
    data[offset] ^= 0xFF
    damaged = tmp_path / "damaged.din.zst"
    damaged.write_bytes(bytes(data))
    with pytest.raises(nodetrace.FormatError) as error:
        nodetrace.open(str(damaged)).records()
    assert str(error.value) == tracetool_error(damaged)
    assert isinstance(error.value, ValueError)


def test_bad_record_raises_format_error_naming_the_record(tmp_path):
    path = tmp_path / "bad.din"
    path.write_text("0 100\n0 10g\n")
    with pytest.raises(nodetrace.FormatError) as error:
        nodetrace.open(str(path)).records()
    assert str(error.value) == tracetool_error(path)
    assert "record 2" in str(error.value)


def test_missing_file_raises_os_error(tmp_path):
    with pytest.raises(OSError) as error:
        nodetrace.open(str(tmp_path / "missing.din.zst"))
    assert "missing.din.zst" in str(error.value)


def test_wrong_informat_raises_value_error(traces):
    with pytest.raises(ValueError, match="informat: expected din, xdin or binary, got 'dinn'"):
        nodetrace.open(str(traces["din"]), informat="dinn")
