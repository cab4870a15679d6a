// actors/vtk_writer.h: VTK XML output (.vtu frames, .pvd series) for ParaView.
#include "defines.h"
#include "support/params_class.h"

namespace superdex::python {

namespace {

DynamicArray<VtkPointData> LoadData(py::handle value, std::string const& field) {
  return FieldTraits<DynamicArray<VtkPointData>>::Load(value, field);
}

}  // namespace

void DefineVtkWriter(py::module_& m) {
  m.attr("VTK_POLY_LINE") = kVtkPolyLine;
  m.attr("VTK_TRIANGLE") = kVtkTriangle;
  m.attr("VTK_TETRA") = kVtkTetra;

  using D = VtkPointData;
  ParamsClass<D>(
      m, "VtkPointData",
      "A named data array, `components` values per point (or per cell), point after point.")
      .Field("name", &D::name, "non-empty, distinct within a file")
      .Field("components", &D::components, "1 = scalar, 3 = vector, ...")
      .Field("values", &D::values, "components × count values");

  m.def(
       "write_vtu",
       [](std::string const& path, py::handle points, py::handle tetrahedra, py::handle triangles,
          py::handle pointData, py::handle cellData) {
         DynamicArray<Real3> const x = LoadPoints(points, "points");
         auto const tets = LoadIndexTuples<4>(tetrahedra, "tetrahedra");
         auto const tris = LoadIndexTuples<3>(triangles, "triangles");
         DynamicArray<VtkPointData> const pd = LoadData(pointData, "point_data");
         DynamicArray<VtkPointData> const cd = LoadData(cellData, "cell_data");
         Checked([&](Error& e) { WriteVtu(path, x, tets, tris, pd, cd, e); });
       },
       py::arg("path"), py::arg("points"), py::arg("tetrahedra") = py::list(),
       py::arg("triangles") = py::list(), py::arg("point_data") = py::list(),
       py::arg("cell_data") = py::list(),
       "Writes one .vtu frame: points (n, 3), then cells: all tetrahedra (m, 4) first, then all "
       "triangles (k, 3). point_data / cell_data: lists of VtkPointData. Validates everything "
       "and writes nothing on bad input; the file is replaced atomically.")
      .def(
          "write_vtu_polylines",
          [](std::string const& path, py::handle points,
             std::vector<std::vector<int>> const& polylines, py::handle pointData) {
            DynamicArray<Real3> const x = LoadPoints(points, "points");
            DynamicArray<VtkPointData> const pd = LoadData(pointData, "point_data");
            Checked([&](Error& e) { WriteVtuPolylines(path, x, polylines, pd, e); });
          },
          py::arg("path"), py::arg("points"), py::arg("polylines"),
          py::arg("point_data") = py::list(),
          "Polylines: one VTK_POLY_LINE cell per index list (>= 2 points each).")
      .def(
          "write_rods_vtu",
          [](std::string const& path, std::vector<RodActorRef> const& rods, py::handle extra) {
            DynamicArray<RodActor const*> pointers;
            for (RodActorRef const& rod : rods) pointers.push_back(&rod.Get());
            DynamicArray<VtkPointData> const data = LoadData(extra, "extra");
            Checked([&](Error& e) { WriteRodsVtu(path, pointers, data, e); });
          },
          py::arg("path"), py::arg("rods"), py::arg("extra") = py::list(),
          "Rods (RodActor objects) as polylines with per-point twist, material frame "
          "d1/d2/tangent and velocity, then the `extra` arrays.");

  py::class_<VtkSeries>(
      m, "VtkSeries",
      "A .pvd collection listing .vtu frames with their times; rewritten after every add_frame, "
      "so the listing on disk is always complete.")
      .def(py::init<std::string>(), py::arg("pvd_path"))
      .def(
          "add_frame",
          [](VtkSeries& series, real time, std::string const& file) {
            Checked([&](Error& e) { series.AddFrame(time, file, e); });
          },
          py::arg("time"), py::arg("vtu_file_name"),
          "Appends (time, file) and rewrites the .pvd; the name is written as given (relative "
          "to the .pvd).")
      .def("get_path", &VtkSeries::GetPath)
      .def("get_num_frames", &VtkSeries::GetNumFrames);
}

}  // namespace superdex::python
