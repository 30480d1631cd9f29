#include "cad/step_assembly.h"

#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <Geom_Surface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IMeshTools_Parameters.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Poly_Triangulation.hxx>
#include <STEPCAFControl_ExternFile.hxx>
#include <STEPCAFControl_Reader.hxx>
#include <STEPControl_Reader.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TCollection_AsciiString.hxx>
#include <TDF_Label.hxx>
#include <TDF_LabelSequence.hxx>
#include <TDF_Tool.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <XSControl_WorkSession.hxx>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <map>
#include <system_error>

#include "core/cancel.h"
#include "core/child_process.h"
#include "core/error.h"
#include "geometry/closest_point.h"
#include "geometry/triangle_bvh.h"

namespace ausbau {
namespace {

namespace fs = std::filesystem;

// Valid UTF-8 without control characters (C0, DEL, C1): a name reaches
// terminals, JSON and YAML; anything else becomes '?'.
std::string Printable(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    const int length = c < 0x80 ? 1 : (c >> 5) == 6 ? 2 : (c >> 4) == 14 ? 3 : (c >> 3) == 30 ? 4 : 0;
    bool valid = length > 0 && i + length <= text.size();
    for (int k = 1; valid && k < length; ++k) valid = (static_cast<unsigned char>(text[i + k]) >> 6) == 2;
    // C1 controls (U+0080-U+009F: "\xC2\x80"-"\xC2\x9F") are escape
    // sequences to some terminals, as C0 ones are.
    const bool c1 = valid && length == 2 && c == 0xC2 && static_cast<unsigned char>(text[i + 1]) < 0xA0;
    if (!valid || c < 0x20 || c == 0x7f || c1) {
      out += '?';
      ++i;
      continue;
    }
    out.append(text, i, length);
    i += length;
  }
  return out;
}

std::string Utf8(const TCollection_ExtendedString& text) {
  // A replacement character of 0 converts to UTF-8 (TCollection_AsciiString).
  return Printable(TCollection_AsciiString(text, '\0').ToCString());
}

std::string LabelName(const TDF_Label& label) {
  Handle(TDataStd_Name) name;
  if (!label.FindAttribute(TDataStd_Name::GetID(), name)) return "";
  return Utf8(name->Get());
}

Eigen::Isometry3d ToIsometry(const gp_Trsf& trsf) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) out.matrix()(r, c) = trsf.Value(r + 1, c + 1);
  }
  return out;
}

// A leaf product tessellated once, in its own coordinates.
struct Prototype {
  TriangleMesh mesh;
  int faces = 0, faces_without_triangles = 0;
  int faces_meshed_coarser = 0;        // StepPart::faces_meshed_coarser
  double coarser_chord_error_mm = 0;   // StepPart::coarser_chord_error_mm
  double overlapping_surface_mm2 = 0;  // StepPart::overlapping_surface_mm2
};

// The area of the triangles of `mesh` that lie on a triangle of another
// face of the same solid (face_of, solid_of: per triangle; solid -1: a
// face in no solid, not asked). A valid solid's faces never lie on one
// another; where they do, a face was tessellated over more of its surface
// than its boundary holds. Seen on CAx-IF s1's CATIA V5 export
// (s1-c5-214, HEAD_BACK): a quarter of a sphere whose sides lie on the
// sphere's seam came back from OpenCASCADE 7.6 as the other three
// quarters, over the neighbouring quarter and over HEAD_FRONT's dome, so
// that HEAD_FRONT seemed 1 mm deep in it. On: within `gap` (a few chord
// errors: two faces of one surface, tessellated apart) of the other
// triangle, at a point inside it (not at its edge: faces meeting at a
// sharp angle), with normals within 25 degrees either way.
double OverlappingSurface(const TriangleMesh& mesh, const std::vector<int>& face_of, const std::vector<int>& solid_of,
                          double gap) {
  const int n = static_cast<int>(mesh.triangles.size());
  std::vector<Eigen::Vector3d> normals(n);
  std::vector<double> areas(n);
  for (int t = 0; t < n; ++t) {
    const auto& f = mesh.triangles[t];
    const Eigen::Vector3d cross =
        (mesh.vertices[f[1]] - mesh.vertices[f[0]]).cross(mesh.vertices[f[2]] - mesh.vertices[f[0]]);
    areas[t] = 0.5 * cross.norm();
    normals[t] = areas[t] > 0 ? Eigen::Vector3d(cross.normalized()) : Eigen::Vector3d::Zero();
  }
  const TriangleBvh bvh(mesh.vertices, mesh.triangles);
  double overlap = 0;
  for (int t = 0; t < n; ++t) {
    if (solid_of[t] < 0 || areas[t] == 0) continue;
    const auto& f = mesh.triangles[t];
    const Eigen::Vector3d centre = (mesh.vertices[f[0]] + mesh.vertices[f[1]] + mesh.vertices[f[2]]) / 3.0;
    bool on_other = false;
    bvh.ForEachTriangleNear(centre.array() - gap, centre.array() + gap, [&](int k) {
      if (solid_of[k] != solid_of[t] || face_of[k] == face_of[t] || std::abs(normals[t].dot(normals[k])) < 0.9)
        return true;
      const auto& g = mesh.triangles[k];
      Eigen::Vector3d weights;
      const Eigen::Vector3d nearest =
          ClosestPointOnTriangle(centre, mesh.vertices[g[0]], mesh.vertices[g[1]], mesh.vertices[g[2]],
                                 DegenerateTriangles::kNearestCorner, FaceWeights::kDividedBySum, &weights);
      on_other = (nearest - centre).norm() <= gap && weights.minCoeff() > 0;
      return !on_other;
    });
    if (on_other) overlap += areas[t];
  }
  return overlap;
}

bool HasTriangles(const TopoDS_Face& face) {
  TopLoc_Location location;
  const Handle(Poly_Triangulation) triangles = BRep_Tool::Triangulation(face, location);
  return !triangles.IsNull() && triangles->NbTriangles() > 0;
}

// An upper bound of the chord error of a face's triangles: the largest
// distance between a triangle's centre or an edge's midpoint and the
// surface's point at the same (u, v) average (BRepMesh's own measure);
// 0 where the triangulation has no (u, v) nodes.
double ChordErrorBound(const TopoDS_Face& face) {
  TopLoc_Location location;
  const Handle(Poly_Triangulation) triangles = BRep_Tool::Triangulation(face, location);
  TopLoc_Location surface_location;
  const Handle(Geom_Surface) surface = BRep_Tool::Surface(face, surface_location);
  if (triangles.IsNull() || surface.IsNull() || !triangles->HasUVNodes()) return 0;
  double largest = 0;
  for (int t = 1; t <= triangles->NbTriangles(); ++t) {
    int n[3];
    triangles->Triangle(t).Get(n[0], n[1], n[2]);
    const auto measure = [&](std::initializer_list<int> nodes) {
      gp_XYZ point(0, 0, 0);
      gp_XY uv(0, 0);
      for (const int k : nodes) {
        point += triangles->Node(k).XYZ();
        uv += triangles->UVNode(k).XY();
      }
      point /= static_cast<double>(nodes.size());
      uv /= static_cast<double>(nodes.size());
      // Nodes are in the triangulation's frame, the surface in its own.
      const gp_Pnt on_surface = surface->Value(uv.X(), uv.Y()).Transformed(surface_location.Transformation());
      largest = std::max(largest, gp_Pnt(point).Transformed(location.Transformation()).Distance(on_surface));
    };
    measure({n[0], n[1], n[2]});
    measure({n[0], n[1]});
    measure({n[1], n[2]});
    measure({n[2], n[0]});
  }
  return largest;
}

// The shape's faces as triangles, welded where two faces share a vertex
// bit for bit (OpenCASCADE discretises a shared edge once, so the faces of
// a closed solid meet at identical points).
Prototype Tessellate(const TopoDS_Shape& shape, const StepTessellation& tessellation) {
  // Not in parallel: the triangles, and so every answer downstream, must
  // not depend on the threads.
  BRepMesh_IncrementalMesh mesher(shape, tessellation.deflection_mm, Standard_False,
                                  tessellation.angular_deflection_rad, Standard_False);
  Prototype out;
  // A face BRepMesh fails on at the chord error asked for is tried again
  // alone with a coarser interior (its edges keep theirs, shared with its
  // neighbours, so it still welds to them). Seen on the Voron Stealthburner
  // bowden module (Fusion 360): 45-degree chamfer cones 0.6 mm wide round
  // a hole, failed at 0.02 mm inside (BRepMesh_Failure), meshed at 0.04;
  // left out, each made its part an open shell with a hole.
  for (TopExp_Explorer face_it(shape, TopAbs_FACE); face_it.More(); face_it.Next()) {
    const TopoDS_Face& face = TopoDS::Face(face_it.Current());
    if (HasTriangles(face)) continue;
    for (double coarser = 2; coarser <= 16 && !HasTriangles(face); coarser *= 2) {
      IMeshTools_Parameters parameters;
      parameters.Deflection = tessellation.deflection_mm;
      parameters.Angle = tessellation.angular_deflection_rad;
      parameters.DeflectionInterior = coarser * tessellation.deflection_mm;
      parameters.AngleInterior = tessellation.angular_deflection_rad;
      parameters.Relative = Standard_False;
      parameters.InParallel = Standard_False;
      BRepMesh_IncrementalMesh retry(face, parameters);
    }
    if (HasTriangles(face)) {
      ++out.faces_meshed_coarser;
      out.coarser_chord_error_mm = std::max(out.coarser_chord_error_mm, ChordErrorBound(face));
    }
  }
  std::map<std::array<double, 3>, int> index_of;
  // Per triangle, its face and its solid (OverlappingSurface).
  TopTools_IndexedMapOfShape solids;
  TopExp::MapShapes(shape, TopAbs_SOLID, solids);
  std::map<const TopoDS_TShape*, int> solid_of_face;
  for (int s = 1; s <= solids.Extent(); ++s)
    for (TopExp_Explorer face_it(solids(s), TopAbs_FACE); face_it.More(); face_it.Next())
      solid_of_face.emplace(face_it.Current().TShape().get(), s - 1);
  std::vector<int> face_of, solid_of;
  for (TopExp_Explorer face_it(shape, TopAbs_FACE); face_it.More(); face_it.Next()) {
    const TopoDS_Face& face = TopoDS::Face(face_it.Current());
    ++out.faces;
    const auto solid = solid_of_face.find(face.TShape().get());
    TopLoc_Location location;
    const Handle(Poly_Triangulation) triangles = BRep_Tool::Triangulation(face, location);
    if (triangles.IsNull() || triangles->NbTriangles() == 0) {
      ++out.faces_without_triangles;
      continue;
    }
    const gp_Trsf& trsf = location.Transformation();
    std::vector<int> node_index(triangles->NbNodes() + 1, -1);
    for (int n = 1; n <= triangles->NbNodes(); ++n) {
      const gp_Pnt p = triangles->Node(n).Transformed(trsf);
      const std::array<double, 3> key{p.X(), p.Y(), p.Z()};
      const auto [it, added] = index_of.emplace(key, static_cast<int>(out.mesh.vertices.size()));
      if (added) out.mesh.vertices.emplace_back(p.X(), p.Y(), p.Z());
      node_index[n] = it->second;
    }
    const bool reversed = face.Orientation() == TopAbs_REVERSED;
    for (int t = 1; t <= triangles->NbTriangles(); ++t) {
      int a = 0, b = 0, c = 0;
      triangles->Triangle(t).Get(a, b, c);
      if (reversed) std::swap(b, c);
      const std::array<int, 3> tri{node_index[a], node_index[b], node_index[c]};
      if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) continue;  // degenerate after welding
      out.mesh.triangles.push_back(tri);
      face_of.push_back(out.faces);
      solid_of.push_back(solid == solid_of_face.end() ? -1 : solid->second);
    }
  }
  out.overlapping_surface_mm2 = OverlappingSurface(out.mesh, face_of, solid_of, 3 * tessellation.deflection_mm);
  return out;
}

// A name that says nothing of the part: empty, what kind of shape a node
// is, only a number (an instance's index: OpenCASCADE's own export of dm1
// names its instances "1", "2", ...), or an identifier CATIA V5 made up
// ("*DIT33", "*MASTER": CAx-IF s1-c5's instances, whose products are
// FOOT_FRONT_000, TAIL_TURBINE, ...), or the identifier SolidWorks gives
// every NEXT_ASSEMBLY_USAGE_OCCURRENCE, whose name it leaves blank
// ("NAUO12": CubeFactory's shredder drivetrain, whose products are
// 01_01_09-cylinder_screw_M5x25-DIN912, ...).
bool NamesNothing(const std::string& name) {
  const auto digits = [](std::string::const_iterator begin, std::string::const_iterator end) {
    return std::all_of(begin, end, [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
  };
  if (digits(name.begin(), name.end())) return true;
  if (name.size() > 4 && name.compare(0, 4, "NAUO") == 0 && digits(name.begin() + 4, name.end())) return true;
  if (name.size() > 1 && name[0] == '*' && std::all_of(name.begin() + 1, name.end(), [](char c) {
        return std::isupper(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c));
      }))
    return true;
  std::string upper;
  for (const char c : name) upper += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  for (const char* kind : {"SOLID", "COMPOUND", "COMPSOLID", "SHELL", "FACE", "SHAPE"}) {
    if (upper == kind) return true;
  }
  return false;
}

// Walks the product tree depth-first, placing each leaf instance.
class TreeWalker {
 public:
  TreeWalker(Handle(XCAFDoc_ShapeTool) tool, const StepTessellation& tessellation, StepAssembly* out)
      : tool_(std::move(tool)), tessellation_(tessellation), out_(out) {
    // The products with a shape of their own (not assemblies): what the
    // walk tessellates, once each (the progress's total).
    TDF_LabelSequence shapes;
    tool_->GetShapes(shapes);
    for (int k = 1; k <= shapes.Length(); ++k) products_with_shape_ += !tool_->IsAssembly(shapes.Value(k));
  }

  void Walk(const TDF_Label& label, const TopLoc_Location& location, std::vector<std::string> path,
            const std::string& instance_name, int depth) {
    // A product tree deeper than this is a cycle (a malformed file).
    if (depth > 64) throw InputError("the product tree is deeper than 64 levels (a cycle?)");
    const std::string product = LabelName(label);
    path.push_back(instance_name.empty() ? product : instance_name);
    if (tool_->IsAssembly(label)) {
      TDF_LabelSequence components;
      tool_->GetComponents(label, components, Standard_False);
      for (int k = 1; k <= components.Length(); ++k) {
        const TDF_Label& component = components.Value(k);
        TDF_Label referred;
        if (!tool_->GetReferredShape(component, referred)) continue;
        std::string name = LabelName(component);
        // XCAF names an unnamed instance "=>[0:1:1:2]" after its product's
        // label: no name of the file's.
        if (name.rfind("=>", 0) == 0) name.clear();
        Walk(referred, location * tool_->GetLocation(component), path, name, depth + 1);
      }
      return;
    }
    const TopoDS_Shape shape = XCAFDoc_ShapeTool::GetShape(label);
    if (shape.IsNull()) return;
    TCollection_AsciiString entry;
    TDF_Tool::Entry(label, entry);
    auto it = prototypes_.find(entry.ToCString());
    if (it == prototypes_.end()) {
      ThrowIfCancelled();  // between products (core/cancel.h)
      it = prototypes_.emplace(entry.ToCString(), Tessellate(shape, tessellation_)).first;
      ++out_->products;
      if (tessellation_.progress) tessellation_.progress(out_->products, products_with_shape_);
    }
    const Prototype& prototype = it->second;
    StepPart part;
    // Named after its instance, else its product. Some exporters
    // (Pro/ENGINEER) give a product several representation items, which
    // XCAF makes components named after their shape type ("SOLID",
    // "COMPOUND"): the part is then named after the nearest node above with
    // a name of its own.
    std::vector<std::string> names(path.rbegin(), path.rend());
    names.insert(names.begin() + 1, product);
    for (const std::string& name : names) {
      if (!NamesNothing(name)) {
        part.name = name;
        break;
      }
    }
    part.product = product;
    part.path = std::move(path);
    part.placement = ToIsometry(location.Transformation());
    part.mesh.triangles = prototype.mesh.triangles;
    part.mesh.vertices.reserve(prototype.mesh.vertices.size());
    for (const Eigen::Vector3d& v : prototype.mesh.vertices) part.mesh.vertices.push_back(part.placement * v);
    part.faces = prototype.faces;
    part.faces_without_triangles = prototype.faces_without_triangles;
    part.faces_meshed_coarser = prototype.faces_meshed_coarser;
    part.coarser_chord_error_mm = prototype.coarser_chord_error_mm;
    part.overlapping_surface_mm2 = prototype.overlapping_surface_mm2;
    out_->parts.push_back(std::move(part));
  }

 private:
  Handle(XCAFDoc_ShapeTool) tool_;
  const StepTessellation& tessellation_;
  StepAssembly* out_;
  std::map<std::string, Prototype> prototypes_;
  int products_with_shape_ = 0;
};

StepAssembly ReadWithOpenCascade(const fs::path& path, const StepTessellation& tessellation) {
  // OpenCASCADE's reader reports on std::cout; a stage's stdout is its
  // result, so its messages are dropped (errors come back as statuses).
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_Printer));
  Handle(TDocStd_Document) document;
  XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", document);
  STEPCAFControl_Reader reader;
  reader.SetNameMode(Standard_True);
  // An assembly split into several files names the others relative to its
  // own folder (DOCUMENT_FILE); OpenCASCADE resolves them against the
  // folder of the path it is given only where that path is absolute (else
  // against the working folder, where they are not).
  if (reader.ReadFile(fs::absolute(path).c_str()) != IFSelect_RetDone) {
    throw InputError("not a readable STEP file (OpenCASCADE's STEP reader refused it)");
  }
  StepAssembly out;
  TColStd_SequenceOfAsciiString lengths, angles, solid_angles;
  reader.ChangeReader().FileUnits(lengths, angles, solid_angles);
  if (lengths.Length() > 0) out.file_units = Printable(lengths.Value(1).ToCString());
  if (!reader.Transfer(document)) throw InputError("OpenCASCADE could not translate the STEP file's shapes");
  // A part in a file that could not be read would be missing from every
  // scene's S, where it might hold D: no scene is written without it.
  std::vector<std::string> unread;
  for (NCollection_DataMap<TCollection_AsciiString, Handle(STEPCAFControl_ExternFile)>::Iterator it(
           reader.ExternFiles());
       it.More(); it.Next()) {
    const Handle(STEPCAFControl_ExternFile)& file = it.Value();
    if (file.IsNull() || file->GetLoadStatus() != IFSelect_RetDone || !file->GetTransferStatus())
      unread.push_back(Printable(it.Key().ToCString()));
  }
  if (!unread.empty()) {
    std::sort(unread.begin(), unread.end());
    std::string list;
    for (const std::string& file : unread) list += (list.empty() ? "" : ", ") + file;
    throw InputError("it refers to parts in other STEP files that could not be read (" + list + ", looked for in " +
                     fs::absolute(path).lexically_normal().parent_path().string() + ")");
  }
  const Handle(XCAFDoc_ShapeTool) tool = XCAFDoc_DocumentTool::ShapeTool(document->Main());
  TDF_LabelSequence roots;
  tool->GetFreeShapes(roots);
  TreeWalker walker(tool, tessellation, &out);
  for (int k = 1; k <= roots.Length(); ++k) walker.Walk(roots.Value(k), TopLoc_Location(), {}, "", 0);
  XCAFApp_Application::GetApplication()->Close(document);
  return out;
}

// The child's result as bytes (RunInChildProcess): plain fields in order.
class Bytes {
 public:
  void Put(const void* data, std::size_t size) { text_.append(static_cast<const char*>(data), size); }
  template <class T>
  void Put(const T& value) {
    Put(&value, sizeof value);
  }
  void PutString(const std::string& s) {
    Put<std::uint64_t>(s.size());
    Put(s.data(), s.size());
  }
  std::string& Text() { return text_; }

 private:
  std::string text_;
};

class BytesReader {
 public:
  explicit BytesReader(const std::string& text) : text_(text) {}
  void Get(void* data, std::size_t size) {
    if (size > text_.size() - at_) throw std::runtime_error("STEP reader: truncated result from the child process");
    std::memcpy(data, text_.data() + at_, size);
    at_ += size;
  }
  template <class T>
  T Get() {
    T value;
    Get(&value, sizeof value);
    return value;
  }
  std::string GetString() {
    const auto size = Get<std::uint64_t>();
    if (size > text_.size() - at_) throw std::runtime_error("STEP reader: truncated result from the child process");
    std::string s = text_.substr(at_, size);
    at_ += size;
    return s;
  }

 private:
  const std::string& text_;
  std::size_t at_ = 0;
};

std::string Serialize(const StepAssembly& assembly) {
  Bytes out;
  out.PutString(assembly.file_units);
  out.Put<std::int64_t>(assembly.products);
  out.Put<std::uint64_t>(assembly.parts.size());
  for (const StepPart& part : assembly.parts) {
    out.PutString(part.name);
    out.PutString(part.product);
    out.Put<std::uint64_t>(part.path.size());
    for (const std::string& p : part.path) out.PutString(p);
    out.Put(part.placement.matrix().data(), sizeof(double) * 16);
    out.Put<std::int64_t>(part.faces);
    out.Put<std::int64_t>(part.faces_without_triangles);
    out.Put<std::int64_t>(part.faces_meshed_coarser);
    out.Put<double>(part.coarser_chord_error_mm);
    out.Put<double>(part.overlapping_surface_mm2);
    out.Put<std::uint64_t>(part.mesh.vertices.size());
    out.Put(part.mesh.vertices.data(), sizeof(Eigen::Vector3d) * part.mesh.vertices.size());
    out.Put<std::uint64_t>(part.mesh.triangles.size());
    out.Put(part.mesh.triangles.data(), sizeof(std::array<int, 3>) * part.mesh.triangles.size());
  }
  return std::move(out.Text());
}

StepAssembly Deserialize(const std::string& bytes) {
  BytesReader in(bytes);
  StepAssembly out;
  out.file_units = in.GetString();
  out.products = static_cast<int>(in.Get<std::int64_t>());
  const auto parts = in.Get<std::uint64_t>();
  for (std::uint64_t k = 0; k < parts; ++k) {
    StepPart part;
    part.name = in.GetString();
    part.product = in.GetString();
    const auto depth = in.Get<std::uint64_t>();
    for (std::uint64_t d = 0; d < depth; ++d) part.path.push_back(in.GetString());
    in.Get(part.placement.matrix().data(), sizeof(double) * 16);
    part.faces = static_cast<int>(in.Get<std::int64_t>());
    part.faces_without_triangles = static_cast<int>(in.Get<std::int64_t>());
    part.faces_meshed_coarser = static_cast<int>(in.Get<std::int64_t>());
    part.coarser_chord_error_mm = in.Get<double>();
    part.overlapping_surface_mm2 = in.Get<double>();
    part.mesh.vertices.resize(in.Get<std::uint64_t>());
    in.Get(part.mesh.vertices.data(), sizeof(Eigen::Vector3d) * part.mesh.vertices.size());
    part.mesh.triangles.resize(in.Get<std::uint64_t>());
    in.Get(part.mesh.triangles.data(), sizeof(std::array<int, 3>) * part.mesh.triangles.size());
    out.parts.push_back(std::move(part));
  }
  return out;
}

}  // namespace

bool IsStepFileName(const fs::path& path) {
  std::string extension = path.extension().string();
  for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return extension == ".step" || extension == ".stp" || extension == ".p21";
}

StepAssembly ReadStepAssembly(const fs::path& path, const StepTessellation& tessellation) {
  const std::string name = path.string();
  for (const auto& [value, flag] : {std::pair{tessellation.deflection_mm, "--deflection"},
                                    std::pair{tessellation.angular_deflection_rad, "--angular-deflection"}}) {
    if (!std::isfinite(value) || value <= 0) {
      throw InputError(std::string(flag) + ": must be a finite number > 0 (got " + std::to_string(value) + ")");
    }
  }
  if (tessellation.angular_deflection_rad > 1.5) {
    throw InputError("--angular-deflection: must be at most 1.5 rad (got " +
                     std::to_string(tessellation.angular_deflection_rad) + ")");
  }
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error || !fs::exists(status)) throw InputErrorAt(name, "file not found");
  if (!fs::is_regular_file(status)) throw InputErrorAt(name, "not a regular file");
  {
    // The STEP physical file's first keyword (ISO 10303-21): a clear
    // message for a file of another format with a STEP name.
    std::ifstream in(path, std::ios::binary);
    std::string head(64, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(in.gcount()));
    if (head.rfind("\xEF\xBB\xBF", 0) == 0) head.erase(0, 3);
    const std::size_t first = head.find_first_not_of(" \t\r\n");
    if (first == std::string::npos || head.compare(first, 12, "ISO-10303-21") != 0) {
      throw InputErrorAt(name, "not a STEP file (it does not begin with ISO-10303-21;)");
    }
  }
  // OpenCASCADE's parser is not hardened against malformed files; a crash
  // there must be an input error, not the death of the stage.
  const std::string bytes = RunInChildProcess(
      [&] {
        try {
          return Serialize(ReadWithOpenCascade(path, tessellation));
        } catch (const InputError& e) {
          throw InputErrorAt(name, e.what());
        } catch (const Standard_Failure& e) {
          throw InputErrorAt(name, std::string("OpenCASCADE failed on it: ") + e.GetMessageString());
        }
      },
      name, "OpenCASCADE's STEP reader");
  StepAssembly assembly = Deserialize(bytes);
  long long triangles = 0;
  for (const StepPart& part : assembly.parts) triangles += static_cast<long long>(part.mesh.triangles.size());
  if (assembly.parts.empty()) throw InputErrorAt(name, "holds no shape (no product with geometry)");
  if (triangles == 0) throw InputErrorAt(name, "no triangle after tessellation (no surface in its shapes)");
  return assembly;
}

}  // namespace ausbau
