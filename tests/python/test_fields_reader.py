"""needlesim.FieldSeries reads any XDMF + HDF5 series as the index names it: any
number of components, any topology, moved points, units from HDF5 attributes;
files it cannot read are refused with the file named."""
import h5py
import numpy as np
import pytest

import needlesim

XDMF = """<?xml version="1.0" ?>
<Xdmf Version="3.0"><Domain>
<Grid Name="series" GridType="Collection" CollectionType="Temporal">
<Grid Name="step0" GridType="Uniform"><Time Value="0"/>
<Topology TopologyType="Polyline" NumberOfElements="3"><DataItem Dimensions="3 2" NumberType="Int" Format="HDF">s.h5:/mesh/cells</DataItem></Topology>
<Geometry GeometryType="XY"><DataItem Dimensions="4 2" Format="HDF">s.h5:/mesh/points</DataItem></Geometry>
<Attribute Name="displacement" AttributeType="Vector" Center="Node"><DataItem Dimensions="4 3" Format="HDF">s.h5:/step000000/point/displacement</DataItem></Attribute>
<Attribute Name="force" AttributeType="Scalar" Center="Cell"><DataItem Dimensions="3" Format="HDF">s.h5:/step000000/cell/force</DataItem></Attribute>
</Grid>
<Grid Name="step1" GridType="Uniform"><Time Value="0.25"/>
<Topology TopologyType="Polyline" NumberOfElements="3"><DataItem Dimensions="3 2" NumberType="Int" Format="HDF">s.h5:/mesh/cells</DataItem></Topology>
<Geometry GeometryType="XY"><DataItem Dimensions="4 2" Format="HDF">s.h5:/step000001/points</DataItem></Geometry>
<Attribute Name="displacement" AttributeType="Vector" Center="Node"><DataItem Dimensions="4 3" Format="HDF">s.h5:/step000001/point/displacement</DataItem></Attribute>
<Attribute Name="force" AttributeType="Scalar" Center="Cell"><DataItem Dimensions="3" Format="HDF">s.h5:/step000001/cell/force</DataItem></Attribute>
</Grid>
</Grid></Domain></Xdmf>
"""


@pytest.fixture
def series(tmp_path):
    points = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]])
    u1 = np.array([[0.0, 0.1, 0.0], [0.0, 0.2, 0.0], [0.0, 0.3, 0.0], [0.0, 0.4, 0.0]])
    with h5py.File(tmp_path / "s.h5", "w") as f:
        f["/mesh/points"] = points
        f["/mesh/cells"] = np.array([[0, 1], [1, 2], [2, 3]], dtype=np.int32)
        f["/step000001/points"] = points + u1[:, :2]
        for k, u in enumerate((np.zeros((4, 3)), u1)):
            f["/step%06d/point/displacement" % k] = u
            f["/step%06d/point/displacement" % k].attrs["unit"] = "m"
            f["/step%06d/cell/force" % k] = np.array([1.0, 2.0, 3.0]) * k
            f["/step%06d/cell/force" % k].attrs["unit"] = np.bytes_(b"N")
    (tmp_path / "s.xdmf").write_text(XDMF)
    return needlesim.FieldSeries(tmp_path / "s.xdmf")


def test_a_series_reads_as_its_index_says(series):
    assert series.name == "s" and len(series) == 2 and series.cell_type == "Polyline"
    np.testing.assert_array_equal(series.times, [0.0, 0.25])
    assert series.points.shape == (4, 2) and series.dim == 2
    np.testing.assert_array_equal(series.cells, [[0, 1], [1, 2], [2, 3]])
    assert series.point_data("displacement").shape == (2, 4, 3)  # 3 components on 2D points
    np.testing.assert_array_equal(series.cell_data("force")[1], [1.0, 2.0, 3.0])
    np.testing.assert_allclose(series[1].points - series.points, series[1].point_data["displacement"][:, :2])
    assert series.units == {"displacement": "m", "force": "N"}
    assert repr(series) == ("<FieldSeries 's': 2 steps, t = 0..0.25 s, 4 points (Polyline); "
                            "point data ['displacement']; cell data ['force']>")


def test_load_reads_every_array_so_the_files_may_go(series, tmp_path):
    series.load()
    (tmp_path / "s.h5").unlink()
    assert series[1].cell_data["force"][2] == 3.0


def test_unreadable_series_name_the_file(tmp_path):
    (tmp_path / "bad.xdmf").write_text("<Xdmf><Domain>")
    with pytest.raises(needlesim.InputError, match="bad.xdmf: is not a readable XDMF file"):
        needlesim.FieldSeries(tmp_path / "bad.xdmf")
    (tmp_path / "xml.xdmf").write_text(XDMF.replace('Format="HDF">s.h5:/mesh/points', 'Format="XML">0 0 1 0'))
    with pytest.raises(needlesim.InputError, match="xml.xdmf: a DataItem in format 'XML'"):
        needlesim.FieldSeries(tmp_path / "xml.xdmf")


def test_a_missing_dataset_names_the_file_and_dataset(tmp_path, series):
    (tmp_path / "gone.xdmf").write_text(XDMF.replace("/step000001/cell/force", "/step000001/cell/missing"))
    gone = needlesim.FieldSeries(tmp_path / "gone.xdmf")
    with pytest.raises(needlesim.InputError, match="s.h5: has no dataset /step000001/cell/missing"):
        gone[1].cell_data["force"]
