#!/usr/bin/python3
"""One harness snapshot written again by VTK's own XML writers, in every encoding they have.

Run with Debian's Python (python3-vtk9, numpy):

    /usr/bin/python3 scripts/vtk_encodings.py --source SNAPSHOT.vtu --out DIR

The committed set (tests/data/external/vtk-encodings/, its README.md) was made from the
snapshot at t = 0.5 of

    signorini run scenes/bar2d.json --scheme crank-nicolson --mass standard --nx 10 \\
        --fields-every-step --out /tmp/src

(``/tmp/src/field-t0.500.vtu``, named ``field-t0.5.vtu`` when it was written: 22 points, 10 quads, the point arrays ``displacement``,
``velocity`` (3 components), ``von_mises``, ``contact_multiplier`` and the cell array
``von_mises``, all Float64), copied into DIR as ``source.vtu``. No discrete problem is solved
here: the script re-encodes that snapshot.

**What it writes.** ``vtkXMLUnstructuredGridReader`` reads the snapshot and
``vtkXMLUnstructuredGridWriter`` writes it once per combination of

- data mode: ``ascii`` (``SetDataModeToAscii``), ``binary`` (inline base64,
  ``SetDataModeToBinary``), ``appended-raw`` and ``appended-base64`` (``SetDataModeToAppended``
  with ``EncodeAppendedData`` off and on);
- compressor (not for ASCII, which has none): ``none``, ``zlib``, ``lz4``
  (``SetCompressorTypeToNone``, ``…ToZLib``, ``…ToLZ4``; VTK's default block size, 32768 bytes,
  so each array here is one compressed block);
- header type (not for ASCII): ``uint32``, ``uint64`` (``SetHeaderTypeToUInt32``, ``…UInt64``);
- precision of the points and of every point array: ``f64`` as read, or ``f32``: a
  ``vtkFloatArray`` copy of each (the cell array and the cells are left as read);

named ``MODE[-COMPRESSOR-HEADER]-PRECISION.vtu``, e.g. ``ascii-f64.vtu``,
``binary-zlib-uint32-f32.vtu``, ``appended-raw-lz4-uint64-f64.vtu`` (38 files). The writer's
other settings are its defaults (byte order: the machine's, little-endian here; ``IdType``
64: the connectivity and offsets as Int64). Its default encoding is one of them:
``appended-base64-zlib-uint32-f64.vtu``.

With the default block size every array here fits in one block, so 6 more files are written
with a small ``BlockSize``, their compressed arrays in several blocks (suffix ``-block<BYTES>``):
4 with 64-byte blocks (``binary-zlib-uint64-f32``, ``appended-raw-zlib-uint32-f64``,
``appended-raw-lz4-uint64-f64``, ``appended-base64-lz4-uint32-f32``), whose point arrays end
with a shorter block, and 2 with 88-byte blocks (``appended-raw-lz4-uint32-f64``,
``appended-base64-zlib-uint64-f64``), where every Float64 point array and the points are a whole
number of blocks (528 bytes = 6 × 88, 176 = 2 × 88). The compression header is ``[blocks, block
size, last block's size, compressed size of each block]``; when the data fill the last block VTK
writes its size as 0, not the block size (the 88-byte files' point arrays, and in the 64-byte
files the Int64 connectivity, 320 bytes = 5 × 64).

Every file so far is little-endian, this machine's order; 3 more are written big-endian
(``SetByteOrderToBigEndian``: ``byte_order="BigEndian"``, the data and the headers swapped),
suffix ``-bigendian``: ``binary-zlib-uint64-f64``, ``appended-raw-none-uint64-f64``,
``appended-raw-zlib-uint32-f32``.

Then one parallel grid, ``parallel.pvtu``, by ``vtkXMLPUnstructuredGridWriter`` with its default
encoding: the grid in 2 pieces, cells 0–4 (y ≤ 0.5) and cells 5–9 (y ≥ 0.5), each a
``vtkExtractCells`` of the snapshot, so the row of nodes at y = 0.5 is in both pieces, as a
parallel run's shared nodes are. Piece 0 owns them: each piece carries a point array
``vtkGhostType`` (UInt8), 0 on the points it owns and ``vtkDataSetAttributes::DUPLICATEPOINT`` (1)
on the copies piece 1 holds of piece 0's points. The writer asks its input for each piece
through the pipeline (``UPDATE_PIECE_NUMBER``), so the pieces come from a small
``VTKPythonAlgorithmBase`` source; they are written as ``parallel_0.vtu``, ``parallel_1.vtu``.

**What VTK 9.1.0 writes** (Debian bookworm's 9.1.0+really9.1.0+dfsg2-5+deb12u1), read off the
files this script wrote:

- ``byte_order="LittleEndian"`` in every file but the ``-bigendian`` ones; ``header_type`` as
  set, with ``version="0.1"`` for ``UInt32`` and ``version="1.0"`` for ``UInt64``;
- ``compressor="vtkZLibDataCompressor"`` for zlib, ``"vtkLZ4DataCompressor"`` for LZ4, no
  attribute for none;
- the ASCII files say ``header_type="UInt32" compressor="vtkZLibDataCompressor"`` (the writer's
  defaults) although their data are ASCII, neither compressed nor headed;
- ``format="ascii"``, ``"binary"`` (inline base64), or ``"appended"`` with an ``offset`` and an
  ``<AppendedData encoding="raw">`` or ``encoding="base64"`` element; the appended raw files
  have no ``<?xml version="1.0"?>`` declaration (the others do); in appended mode (raw and
  base64) the attributes the writer fills in afterwards (``NumberOfPoints``,
  ``NumberOfCells``, ``RangeMin``, ``RangeMax``, ``offset``) are followed by padding spaces
  outside their quotes (``offset="0"`` then 19 spaces), and ``RangeMin``/``RangeMax`` have 11
  significant digits (as many as a double needs, up to 17, in the other modes);
- each array's ``RangeMin``/``RangeMax``; for the 3-component arrays (``displacement``,
  ``velocity``, ``Points``) they are the range of the vectors' norm, also written as an
  ``<InformationKey name="L2_NORM_RANGE" location="vtkDataArray">`` child of the array;
- the f32 files: points and point arrays ``Float32``, the cell array ``von_mises`` ``Float64``,
  connectivity and offsets ``Int64``, types ``UInt8``;
- the parallel grid, with the writer's defaults (appended base64, zlib, ``UInt32`` headers,
  ``version="0.1"``, in the ``.pvtu`` and in its pieces): ``<PUnstructuredGrid
  GhostLevel="0">`` (no ghost cells); ghost points marked only by the point array
  ``vtkGhostType`` (``UInt8``, listed in ``PPointData`` like the others); ``vtkExtractCells``
  adds the cell array ``vtkOriginalCellIds`` (``Int64``, ``IdType="1"``); the pieces listed as
  ``<Piece Source="parallel_0.vtu"/>``, ``<Piece Source="parallel_1.vtu"/>``.

The script prints these attributes for each file it writes, and its size.

**The check.** Every file is read back by ``vtkXMLUnstructuredGridReader`` (the parallel grid by
``vtkXMLPUnstructuredGridReader``) and asserted to hold the source's values to the precision of
its type: the Float64 files bit for bit; the Float32 files as the source's values rounded to
Float32, bit for bit (so within 2⁻²⁴ relative of the source), their arrays of type Float32; the
cells and the cell array bit for bit in every file. The parallel grid reads back as 24 points
(the 2 shared nodes twice) and 10 cells, every point with the source's coordinates and values,
every cell on the points of the source's cell its ``vtkOriginalCellIds`` names, and
``vtkGhostType`` 1 on exactly the 2 copies in piece 1.
"""

import argparse
import itertools
import pathlib
import re
import shutil

import numpy as np
import vtk
from vtkmodules.util import numpy_support
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase

MODES = ["ascii", "binary", "appended-raw", "appended-base64"]
COMPRESSORS = ["none", "zlib", "lz4"]
HEADERS = ["uint32", "uint64"]
PRECISIONS = ["f64", "f32"]
SMALL_BLOCKS = [
    ("binary", "zlib", "uint64", "f32", 64),
    ("appended-raw", "zlib", "uint32", "f64", 64),
    ("appended-raw", "lz4", "uint64", "f64", 64),
    ("appended-base64", "lz4", "uint32", "f32", 64),
    ("appended-raw", "lz4", "uint32", "f64", 88),
    ("appended-base64", "zlib", "uint64", "f64", 88),
]
BIG_ENDIAN = [
    ("binary", "zlib", "uint64", "f64"),
    ("appended-raw", "none", "uint64", "f64"),
    ("appended-raw", "zlib", "uint32", "f32"),
]


def read(path, reader_class=vtk.vtkXMLUnstructuredGridReader):
    """The grid in ``path`` as ``reader_class`` reads it."""
    reader = reader_class()
    reader.SetFileName(str(path))
    reader.Update()
    if reader.GetErrorCode() != 0:
        raise RuntimeError(f"VTK could not read {path}")
    grid = vtk.vtkUnstructuredGrid()
    grid.DeepCopy(reader.GetOutput())
    return grid


def float32_copy(array):
    """A ``vtkFloatArray`` with the values, name and components of ``array``."""
    copy = vtk.vtkFloatArray()
    copy.DeepCopy(array)
    copy.SetName(array.GetName())
    return copy


def in_float32(grid):
    """``grid`` with its points and every point array as ``vtkFloatArray`` copies."""
    single = vtk.vtkUnstructuredGrid()
    single.DeepCopy(grid)
    points = vtk.vtkPoints()
    points.SetData(float32_copy(grid.GetPoints().GetData()))
    single.SetPoints(points)
    data = single.GetPointData()
    for k in range(grid.GetPointData().GetNumberOfArrays()):
        array = grid.GetPointData().GetArray(k)
        data.RemoveArray(array.GetName())
        data.AddArray(float32_copy(array))
    return single


def configure(writer, mode, compressor, header):
    """Sets ``writer``'s data mode, compressor and header type."""
    if mode == "ascii":
        writer.SetDataModeToAscii()
        return
    if mode == "binary":
        writer.SetDataModeToBinary()
    else:
        writer.SetDataModeToAppended()
        writer.SetEncodeAppendedData(mode == "appended-base64")
    {
        "none": writer.SetCompressorTypeToNone,
        "zlib": writer.SetCompressorTypeToZLib,
        "lz4": writer.SetCompressorTypeToLZ4,
    }[compressor]()
    {"uint32": writer.SetHeaderTypeToUInt32, "uint64": writer.SetHeaderTypeToUInt64}[header]()


def write(grid, path, mode, compressor, header, block_size=None, big_endian=False):
    """Writes ``grid`` to ``path`` with ``vtkXMLUnstructuredGridWriter``; ``block_size``, if
    given, is the writer's ``BlockSize`` (the bytes of data per compressed block); with
    ``big_endian`` the data and headers are big-endian (``SetByteOrderToBigEndian``)."""
    writer = vtk.vtkXMLUnstructuredGridWriter()
    writer.SetInputData(grid)
    writer.SetFileName(str(path))
    configure(writer, mode, compressor, header)
    if block_size is not None:
        writer.SetBlockSize(block_size)
    if big_endian:
        writer.SetByteOrderToBigEndian()
    if writer.Write() != 1:
        raise RuntimeError(f"VTK could not write {path}")


def values(array):
    """The values of ``array`` as a numpy array (components as columns)."""
    return numpy_support.vtk_to_numpy(array)


def point_arrays(grid):
    """The point arrays of ``grid`` by name."""
    data = grid.GetPointData()
    return {data.GetArrayName(k): data.GetArray(k) for k in range(data.GetNumberOfArrays())}


def expected(array, precision):
    """The values of the source's ``array`` as a file of ``precision`` holds them."""
    v = values(array)
    return v.astype(np.float32) if precision == "f32" else v


def assert_same(name, got, want):
    """Asserts the arrays are equal bit for bit, of the same dtype."""
    assert got.dtype == want.dtype, f"{name}: {got.dtype}, expected {want.dtype}"
    assert got.shape == want.shape, f"{name}: shape {got.shape}, expected {want.shape}"
    assert got.tobytes() == want.tobytes(), f"{name}: values differ from the source's"


def assert_cells(name, got, source):
    """Asserts ``got``'s cells and cell data are the source's, bit for bit."""
    for part in ["GetConnectivityArray", "GetOffsetsArray"]:
        assert_same(
            f"{name} {part}",
            values(getattr(got.GetCells(), part)()),
            values(getattr(source.GetCells(), part)()),
        )
    assert_same(f"{name} types", values(got.GetCellTypesArray()),
                values(source.GetCellTypesArray()))
    cell = source.GetCellData()
    assert got.GetCellData().GetNumberOfArrays() == cell.GetNumberOfArrays()
    for k in range(cell.GetNumberOfArrays()):
        array = cell.GetArray(k)
        assert_same(f"{name} cell {array.GetName()}",
                    values(got.GetCellData().GetArray(array.GetName())), values(array))


def check(path, source, precision):
    """Asserts that VTK reads back ``path`` as ``source`` in ``precision``."""
    got = read(path)
    name = path.name
    assert_same(f"{name} points", values(got.GetPoints().GetData()),
                expected(source.GetPoints().GetData(), precision))
    want = point_arrays(source)
    have = point_arrays(got)
    assert list(have) == list(want), f"{name}: arrays {list(have)}, expected {list(want)}"
    for array_name, array in want.items():
        assert_same(f"{name} {array_name}", values(have[array_name]), expected(array, precision))
    assert_cells(name, got, source)


def head(path):
    """The XML of ``path`` before its appended data."""
    text = path.read_bytes()
    cut = text.find(b'<AppendedData encoding="raw">')
    return text[: cut if cut >= 0 else len(text)].decode("ascii")


def attributes(path):
    """What ``path`` says of its encoding: the ``VTKFile`` attributes and the arrays' formats."""
    text = head(path)
    root = re.search(r"<VTKFile ([^>]*)>", text).group(1)
    formats = sorted(set(re.findall(r'format="(\w+)"', text)))
    appended = re.findall(r'<AppendedData encoding="(\w+)"', text)
    types = sorted(set(re.findall(r'<(?:P)?DataArray type="(\w+)"', text)))
    extra = f" AppendedData encoding={appended[0]}" if appended else ""
    return f"{root}; format {','.join(formats)}{extra}; types {','.join(types)}"


class Pieces(VTKPythonAlgorithmBase):
    """A source of the snapshot's two pieces: the piece the pipeline asks for, with its
    ``vtkGhostType`` point array."""

    def __init__(self, grid, ranges):
        VTKPythonAlgorithmBase.__init__(
            self, nInputPorts=0, nOutputPorts=1, outputType="vtkUnstructuredGrid"
        )
        self.grid = grid
        self.ranges = ranges

    def RequestInformation(self, request, inInfo, outInfo):
        outInfo.GetInformationObject(0).Set(
            vtk.vtkAlgorithm.CAN_HANDLE_PIECE_REQUEST(), 1
        )
        return 1

    def RequestData(self, request, inInfo, outInfo):
        info = outInfo.GetInformationObject(0)
        piece = info.Get(vtk.vtkStreamingDemandDrivenPipeline.UPDATE_PIECE_NUMBER())
        output = vtk.vtkUnstructuredGrid.GetData(info)
        output.ShallowCopy(piece_grid(self.grid, self.ranges, piece))
        return 1


def extracted(grid, first, last):
    """Cells ``first``..=``last`` of ``grid`` with the points they use (``vtkExtractCells``)."""
    extract = vtk.vtkExtractCells()
    extract.SetInputData(grid)
    extract.AddCellRange(first, last)
    extract.Update()
    return extract.GetOutput()


def piece_grid(grid, ranges, piece):
    """Piece ``piece`` of ``grid``: its cell range, and ``vtkGhostType`` 1 (DUPLICATEPOINT) on
    its points that an earlier piece holds."""
    part = vtk.vtkUnstructuredGrid()
    part.DeepCopy(extracted(grid, *ranges[piece]))
    earlier = set()
    for first, last in ranges[:piece]:
        points = values(extracted(grid, first, last).GetPoints().GetData())
        earlier.update(tuple(p) for p in points)
    ghost = np.array(
        [
            vtk.vtkDataSetAttributes.DUPLICATEPOINT if tuple(p) in earlier else 0
            for p in values(part.GetPoints().GetData())
        ],
        dtype=np.uint8,
    )
    array = numpy_support.numpy_to_vtk(ghost, deep=1, array_type=vtk.VTK_UNSIGNED_CHAR)
    array.SetName(vtk.vtkDataSetAttributes.GhostArrayName())
    part.GetPointData().AddArray(array)
    return part


def points_of(grid, cell):
    """The coordinates of the points of ``cell`` of ``grid``, in the cell's order."""
    ids = grid.GetCell(cell).GetPointIds()
    coordinates = values(grid.GetPoints().GetData())
    return coordinates[[ids.GetId(i) for i in range(ids.GetNumberOfIds())]]


def write_parallel(source, out):
    """Writes ``parallel.pvtu`` and its 2 pieces, and checks that VTK reads them back."""
    cells = source.GetNumberOfCells()
    ranges = [(0, cells // 2 - 1), (cells // 2, cells - 1)]
    pieces = Pieces(source, ranges)
    writer = vtk.vtkXMLPUnstructuredGridWriter()
    writer.SetInputConnection(pieces.GetOutputPort())
    writer.SetFileName(str(out / "parallel.pvtu"))
    writer.SetNumberOfPieces(len(ranges))
    writer.SetStartPiece(0)
    writer.SetEndPiece(len(ranges) - 1)
    if writer.Write() != 1:
        raise RuntimeError("VTK could not write parallel.pvtu")

    got = read(out / "parallel.pvtu", vtk.vtkXMLPUnstructuredGridReader)
    source_points = values(source.GetPoints().GetData())
    at = {tuple(p): k for k, p in enumerate(source_points)}
    points = values(got.GetPoints().GetData())
    shared = len(values(extracted(source, *ranges[0]).GetPoints().GetData())) + len(
        values(extracted(source, *ranges[1]).GetPoints().GetData())
    ) - len(source_points)
    assert len(points) == len(source_points) + shared, f"parallel: {len(points)} points"
    assert got.GetNumberOfCells() == cells, f"parallel: {got.GetNumberOfCells()} cells"
    original = values(got.GetCellData().GetArray("vtkOriginalCellIds"))
    assert sorted(original) == list(range(cells)), f"parallel: cells {original}"
    for k, cell in enumerate(original):
        assert_same(f"parallel cell {k}", points_of(got, k), points_of(source, cell))
    order = np.array([at[tuple(p)] for p in points])
    have = point_arrays(got)
    for array_name, array in point_arrays(source).items():
        assert_same(f"parallel {array_name}", values(have[array_name]), values(array)[order])
    ghost = values(have[vtk.vtkDataSetAttributes.GhostArrayName()])
    assert ghost.dtype == np.uint8
    marked = np.flatnonzero(ghost)
    assert len(marked) == shared, f"parallel: ghost points {marked}"
    assert all(ghost[marked] == vtk.vtkDataSetAttributes.DUPLICATEPOINT)
    first_piece = order[: len(values(extracted(source, *ranges[0]).GetPoints().GetData()))]
    assert set(order[marked]) <= set(first_piece), "parallel: a ghost not held by piece 0"
    assert all(m >= len(first_piece) for m in marked), "parallel: a ghost in piece 0"
    return len(points), shared


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--source", type=pathlib.Path, required=True,
                        help="a snapshot the harness wrote (.vtu)")
    parser.add_argument("--out", type=pathlib.Path, required=True, help="the directory to fill")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(args.source, args.out / "source.vtu")
    source = read(args.out / "source.vtu")
    grids = {"f64": source, "f32": in_float32(source)}
    print(f"VTK {vtk.vtkVersion.GetVTKVersion()}")

    combinations = [("ascii", None, None, p) for p in PRECISIONS] + [
        (m, c, h, p)
        for m, c, h, p in itertools.product(MODES[1:], COMPRESSORS, HEADERS, PRECISIONS)
    ]
    for mode, compressor, header, precision in combinations:
        name = "-".join(x for x in (mode, compressor, header, precision) if x) + ".vtu"
        path = args.out / name
        write(grids[precision], path, mode, compressor, header)
        check(path, source, precision)
        print(f"{name} {path.stat().st_size} B: {attributes(path)}; read back")
    for mode, compressor, header, precision, block_size in SMALL_BLOCKS:
        name = f"{mode}-{compressor}-{header}-{precision}-block{block_size}.vtu"
        path = args.out / name
        write(grids[precision], path, mode, compressor, header, block_size)
        check(path, source, precision)
        print(f"{name} {path.stat().st_size} B: {attributes(path)}; read back")
    for mode, compressor, header, precision in BIG_ENDIAN:
        name = f"{mode}-{compressor}-{header}-{precision}-bigendian.vtu"
        path = args.out / name
        write(grids[precision], path, mode, compressor, header, big_endian=True)
        check(path, source, precision)
        print(f"{name} {path.stat().st_size} B: {attributes(path)}; read back")

    points, shared = write_parallel(source, args.out)
    for name in ["parallel.pvtu", "parallel_0.vtu", "parallel_1.vtu"]:
        path = args.out / name
        print(f"{name} {path.stat().st_size} B: {attributes(path)}")
    print(f"parallel.pvtu read back: {points} points ({shared} shared nodes marked in piece 1)")
    print(
        f"{len(combinations) + len(SMALL_BLOCKS) + len(BIG_ENDIAN)} files and the parallel grid "
        "read back as the source"
    )


if __name__ == "__main__":
    main()
