#include "step_fixture.h"

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_Printer.hxx>
#include <STEPCAFControl_Writer.hxx>
#include <STEPControl_Controller.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <cmath>
#include <gp_Ax1.hxx>
#include <gp_Ax2.hxx>
#include <stdexcept>

namespace ausbau::testing {
namespace {

// A translation, after a turn of `degrees` about z.
TopLoc_Location At(double x, double y, double z, double degrees = 0) {
  gp_Trsf turn, move;
  turn.SetRotation(gp_Ax1(gp_Pnt(0, 0, 0), gp::DZ()), degrees * M_PI / 180);
  move.SetTranslation(gp_Vec(x, y, z));
  return TopLoc_Location(move * turn);
}

void Name(const TDF_Label& label, const char* name) {
  TDataStd_Name::Set(label, TCollection_ExtendedString(name, Standard_True));  // UTF-8
}

}  // namespace

void WriteStepFixture(const std::filesystem::path& file, const StepFixtureOptions& options) {
  // The writer's statistics go to std::cout; not into the test's log.
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_Printer));
  STEPControl_Controller::Init();
  Handle(TDocStd_Document) document;
  XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", document);
  const Handle(XCAFDoc_ShapeTool) tool = XCAFDoc_DocumentTool::ShapeTool(document->Main());

  const TopoDS_Shape box = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(100, 60, 10)).Shape();
  const TopoDS_Shape bore = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(30, 30, -1), gp::DZ()), 5, 12).Shape();
  const TopoDS_Shape plate = BRepAlgoAPI_Cut(box, bore).Shape();
  const TopoDS_Shape pin = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp::DZ()), 5 - options.gap_mm, 30).Shape();
  const TopoDS_Shape stud = BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, 0), gp::DZ()), 3, 15).Shape();

  const TDF_Label plate_label = tool->AddShape(plate, Standard_False);
  Name(plate_label, options.plate_name.c_str());
  const TDF_Label pin_label = tool->AddShape(pin, Standard_False);
  Name(pin_label, "pin");
  const TDF_Label stud_label = tool->AddShape(stud, Standard_False);
  Name(stud_label, "stud");
  const TDF_Label pair = tool->NewShape();
  Name(pair, "pair");
  tool->AddComponent(pair, stud_label, At(0, 0, 0));
  tool->AddComponent(pair, stud_label, At(20, 0, 0));
  const TDF_Label bench = tool->NewShape();
  Name(bench, "bench");
  tool->AddComponent(bench, plate_label, At(0, 0, 0));
  const TDF_Label pin_instance = tool->AddComponent(bench, pin_label, At(30, 30, -5));
  if (!options.pin_instance_name.empty()) Name(pin_instance, options.pin_instance_name.c_str());
  Name(tool->AddComponent(bench, pair, At(60, 15, 10)), "pair:1");
  Name(tool->AddComponent(bench, pair, At(60, 45, 10, 90)), "pair:2");
  tool->UpdateAssemblies();

  Interface_Static::SetCVal("write.step.unit", options.unit.c_str());
  STEPCAFControl_Writer writer;
  writer.SetNameMode(Standard_True);
  const bool transferred = options.external_prefix.empty()
                               ? writer.Transfer(document, STEPControl_AsIs)
                               : writer.Transfer(document, STEPControl_AsIs, options.external_prefix.c_str());
  // (The other files go beside an absolute path, named as the file says.)
  const IFSelect_ReturnStatus status = writer.Write(std::filesystem::absolute(file).c_str());
  Interface_Static::SetCVal("write.step.unit", "MM");
  XCAFApp_Application::GetApplication()->Close(document);
  if (!transferred || status != IFSelect_RetDone) throw std::runtime_error("WriteStepFixture: writing failed");
}

}  // namespace ausbau::testing
