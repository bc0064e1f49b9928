#pragma once
// CAD files for the tests, made with OpenCASCADE itself: solids built from
// primitives and Booleans, written as STEP (in a chosen unit), IGES or BREP.

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <BRepTools.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <TopoDS_Shape.hxx>

#include <mutex>
#include <stdexcept>
#include <string>

namespace sage::test {

/// OCCT's writers print transfer statistics to stdout: silenced once.
inline void quiet_occt() {
  static std::once_flag once;
  std::call_once(once, [] { Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream)); });
}

/// The block [-1, 1] x [-1, 1] x [0, 1] with a vertical channel of radius
/// 0.4 through it (the CSG model of examples/problems/block_with_hole.json).
/// The cylinder's seam is turned off the axes, so that the tessellation's
/// nodes do not sit on round coordinates.
inline TopoDS_Shape block_with_channel() {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(-1, -1, 0), 2, 2, 1).Shape();
  const TopoDS_Shape channel =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, -1), gp_Dir(0, 0, 1), gp_Dir(0.8, 0.6, 0)), 0.4, 3).Shape();
  return BRepAlgoAPI_Cut(box, channel).Shape();
}

/// `unit` as OCCT's STEP writer names it: "MM", "M", "INCH", "FT", ...
inline void write_step(const TopoDS_Shape& shape, const std::string& path, const char* unit = "MM",
                       STEPControl_StepModelType mode = STEPControl_AsIs) {
  quiet_occt();
  static std::mutex m;  // the unit is a process-wide parameter
  std::lock_guard<std::mutex> lock(m);
  STEPControl_Controller::Init();  // declares the parameters set below
  if (!Interface_Static::SetCVal("write.step.unit", unit)) throw std::runtime_error(std::string("unit ") + unit);
  STEPControl_Writer writer;
  if (writer.Transfer(shape, mode) != IFSelect_RetDone || writer.Write(path.c_str()) != IFSelect_RetDone)
    throw std::runtime_error("cannot write " + path);
  Interface_Static::SetCVal("write.step.unit", "MM");
}

inline void write_iges(const TopoDS_Shape& shape, const std::string& path) {
  quiet_occt();
  IGESControl_Controller::Init();
  IGESControl_Writer writer("MM", 1);  // 1: solids as B-rep entities (MSBO)
  writer.AddShape(shape);
  writer.ComputeModel();
  if (!writer.Write(path.c_str())) throw std::runtime_error("cannot write " + path);
}

inline void write_brep(const TopoDS_Shape& shape, const std::string& path) {
  if (!BRepTools::Write(shape, path.c_str())) throw std::runtime_error("cannot write " + path);
}

}  // namespace sage::test
