#include "shared/model_files/sdf_reading.h"

#include <algorithm>
#include <string_view>
#include <system_error>

#include <sdf/Collision.hh>
#include <sdf/Console.hh>
#include <sdf/Geometry.hh>
#include <sdf/Link.hh>
#include <sdf/Mesh.hh>
#include <sdf/ParserConfig.hh>
#include <sdf/Visual.hh>
#include <sdf/World.hh>
#include <sdf/parser.hh>

#include "shared/common/check.h"
#include "shared/model_files/sdf_mesh_uris.h"
#include "shared/model_files/xml_shape.h"

namespace mbstream::model_files {

namespace {

Eigen::Isometry3d ToIsometry(const ignition::math::Pose3d& pose) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  const ignition::math::Quaterniond& q = pose.Rot();
  X.linear() = Eigen::Quaterniond(q.W(), q.X(), q.Y(), q.Z()).normalized().toRotationMatrix();
  X.translation() = Eigen::Vector3d(pose.Pos().X(), pose.Pos().Y(), pose.Pos().Z());
  return X;
}

void AddMesh(const sdf::Geometry* geometry, std::vector<std::string>* uris) {
  if (geometry == nullptr || geometry->Type() != sdf::GeometryType::MESH) return;
  const sdf::Mesh* mesh = geometry->MeshShape();
  if (mesh == nullptr || mesh->Uri().empty()) return;
  if (std::find(uris->begin(), uris->end(), mesh->Uri()) == uris->end()) {
    uris->push_back(mesh->Uri());
  }
}

// A file path libsdformat gives an element or an error: a real file (an included model's),
// not the "<data-string>" of text loaded from memory.
bool IsFilePath(const std::string& path) { return !path.empty() && path.front() != '<'; }

std::string Joined(const std::vector<std::filesystem::path>& paths) {
  std::string text;
  for (const std::filesystem::path& path : paths)
    text += (text.empty() ? "" : ", ") + path.string();
  return text;
}

// An <include> of model://NAME found at `found` (its folder, or its model.sdf): the folder
// is NAME's, for its meshes' paths (sdf_mesh_uris.h).
void NoteIncludedModel(const std::string& uri, const std::filesystem::path& found,
                       SdfIncludedModels* models) {
  constexpr std::string_view kModel = "model://";
  if (found.empty() || !uri.starts_with(kModel)) return;
  std::string name = uri.substr(kModel.size());
  if (!name.empty() && name.back() == '/') name.pop_back();
  if (name.empty() || name.find('/') != std::string::npos) return;
  std::error_code error;
  const std::filesystem::path folder =
      std::filesystem::is_directory(found, error) ? found : found.parent_path();
  models->emplace(std::filesystem::absolute(folder).lexically_normal(), name);
}

// The include that was not found, as an error naming where the <include> stands.
struct IncludeMiss {
  std::string uri;
  std::vector<std::filesystem::path> tried;
};

[[noreturn]] void ThrowIncludeMiss(const std::string& source, const sdf::Errors& errors,
                                   const IncludeMiss& miss) {
  std::string where = source;
  for (const sdf::Error& error : errors) {
    if (error.Message().find(miss.uri) == std::string::npos) continue;
    if (error.FilePath().has_value() && IsFilePath(*error.FilePath())) where = *error.FilePath();
    if (error.LineNumber().has_value()) where += ":" + std::to_string(*error.LineNumber());
    break;
  }
  const bool model_uri = miss.uri.starts_with("model://");
  throw InputError(where + ": <include> of '" + miss.uri + "': not found; tried " +
                   Joined(miss.tried) + "; " +
                   (model_uri ? "give --package-path DIR (a folder holding the model's folder, "
                                "with its model.config or model.sdf) or set "
                                "MBSTREAM_PACKAGE_PATH"
                              : "check the path (relative to the including file)"));
}

}  // namespace

SdfFile::SdfFile(const std::string& text, std::string source, const SdfLoadOptions& options)
    : root_(std::make_unique<sdf::Root>()), source_(std::move(source)) {
  // libsdformat parses with TinyXML2 9 (Debian's libtinyxml2-9): it stops at its own nesting
  // limit (XML_ELEMENT_DEPTH_EXCEEDED) but counts neither attributes nor elements, and its
  // messages for UTF-16 text or entities mislead. The URDF reader's shape check goes first,
  // with the same limits (docs/reliability.md, "Limits").
  XmlShapeLimits limits;
  limits.links_at_any_depth = true;
  if (options.max_links > 0) limits.max_top_links = options.max_links;
  limits.nesting_note =
      "an SDFormat model nests about 8 deep (sdf, world, model, link, visual, geometry, mesh, "
      "uri)";
  if (!options.includes) {
    limits.refused_element = "include";
    limits.refused_note =
        "the server reads no file a model names (a model:// path, a URL, a file of its own); "
        "give the world to `mbstream submit`, which sends the included models inside it, or "
        "copy the included model's links and joints into this file";
  }
  if (const auto problem = CheckXmlShape(text, limits)) {
    const std::string message =
        source_ + ":" + std::to_string(problem->line) + ": " + problem->what;
    if (problem->over_caller_limit) throw LimitError(message);
    throw InputError(message);
  }
  // SDFormat's errors come back in `errors` and into our message: keep its console quiet.
  sdf::Console::Instance()->SetQuiet(true);
  sdf::ParserConfig config;
  std::vector<IncludeMiss> misses;
  SdfIncludedModels included;
  if (options.includes) {
    config.SetFindCallback([&](const std::string& uri) {
      SdfIncludeSearch search = FindSdfInclude(uri, *options.includes);
      if (search.found.empty()) misses.push_back({uri, std::move(search.tried)});
      NoteIncludedModel(uri, search.found, &included);
      return search.found.string();
    });
  }
  // Root::LoadSdfString's two steps, with the included models' relative mesh paths
  // rewritten between them (sdf_mesh_uris.h).
  sdf::Errors errors;
  const sdf::SDFPtr parsed = std::make_shared<sdf::SDF>();
  sdf::init(parsed);
  if (!sdf::readString(text, config, parsed, errors)) {
    errors.push_back({sdf::ErrorCode::STRING_READ, "unable to read the SDFormat text"});
  } else {
    if (options.includes) RewriteIncludedMeshUris(parsed->Root(), *options.includes, included);
    const sdf::Errors load = root_->Load(parsed, config);
    errors.insert(errors.end(), load.begin(), load.end());
  }
  if (!errors.empty()) {
    if (!misses.empty()) ThrowIncludeMiss(source_, errors, misses.front());
    ThrowSdfErrors(source_, errors);
  }
  if (root_->WorldCount() > 1) {
    throw InputError(source_ + ": the file has " + std::to_string(root_->WorldCount()) +
                     " worlds; give one world (or a top-level <model>)");
  }
  if (const sdf::Model* model = root_->Model(); model != nullptr) {
    title_ = model->Name();
    AddModel(*model, "", Eigen::Isometry3d::Identity(), model->Static(), 0);
  } else if (root_->WorldCount() == 1) {
    const sdf::World& world = *root_->WorldByIndex(0);
    if (world.ModelCount() == 0) {
      throw InputError(Where(world.Element()) + ": world '" + world.Name() +
                       "' has no model; give it a <model> or an <include>");
    }
    if (const sdf::ElementPtr element = world.Element();
        element->HasElement("gravity") &&
        element->GetElement("gravity")->GetExplicitlySetInFile()) {
      const ignition::math::Vector3d g = world.Gravity();
      gravity_ = Eigen::Vector3d(g.X(), g.Y(), g.Z());
      if (!gravity_->allFinite() || gravity_->cwiseAbs().maxCoeff() > 1e4) {
        throw InputError(Where(element->GetElement("gravity")) + ": world '" + world.Name() +
                         "': <gravity> is (" + std::to_string(g.X()) + ", " +
                         std::to_string(g.Y()) + ", " + std::to_string(g.Z()) +
                         ") m/s^2; give finite components within +-1e4 m/s^2 (1,000 g), e.g. "
                         "0 0 -9.81");
      }
    }
    const bool several = world.ModelCount() > 1;
    title_ = several ? world.Name() : world.ModelByIndex(0)->Name();
    for (uint64_t k = 0; k < world.ModelCount(); ++k) {
      const sdf::Model& model = *world.ModelByIndex(k);
      ignition::math::Pose3d X_WM;
      const sdf::Errors pose_errors = model.SemanticPose().Resolve(X_WM, kSdfWorld);
      if (!pose_errors.empty()) {
        throw InputError(Where(model.Element()) + ": model '" + model.Name() +
                         "': its pose cannot be resolved: \"" + pose_errors.front().Message() +
                         "\"; check its relative_to frame");
      }
      AddModel(model, several ? model.Name() + kSdfScope : "", ToIsometry(X_WM), model.Static(),
               static_cast<int>(models_.size()));
    }
  }
  if (models_.empty()) {
    throw InputError(source_ + ": no <model> in the file; give a <model> with links and joints");
  }
  if (options.max_links > 0) {
    uint64_t links = 0;
    for (const SdfModelEntry& entry : models_) links += entry.model->LinkCount();
    if (links > static_cast<uint64_t>(options.max_links)) {
      throw LimitError(source_ + ": more than " + std::to_string(options.max_links) +
                       " <link> elements with the included models, the limit (--max-links); "
                       "split the world or raise the limit");
    }
  }
}

void SdfFile::AddModel(const sdf::Model& model, std::string prefix, const Eigen::Isometry3d& X_WM,
                       bool is_static, int top) {
  models_.push_back({&model, prefix, X_WM, is_static, top});
  for (uint64_t k = 0; k < model.ModelCount(); ++k) {
    const sdf::Model& nested = *model.ModelByIndex(k);
    const Eigen::Isometry3d X_MN = ToIsometry([&] {
      ignition::math::Pose3d pose;
      const sdf::Errors errors = nested.SemanticPose().Resolve(pose, "__model__");
      if (!errors.empty()) {
        throw InputError(Where(nested.Element()) + ": model '" + nested.Name() +
                         "': its pose cannot be resolved: \"" + errors.front().Message() +
                         "\"; check its relative_to frame");
      }
      return pose;
    }());
    AddModel(nested, prefix + nested.Name() + kSdfScope, X_WM * X_MN, is_static || nested.Static(),
             top);
  }
}

std::string SdfFile::ExpandedText() const {
  return "<?xml version=\"1.0\"?>\n" + root_->Element()->ToString("", false, false);
}

std::string SdfFile::Where(const sdf::ElementPtr& element) const {
  if (element == nullptr) return source_;
  const std::string file = IsFilePath(element->FilePath()) ? element->FilePath() : source_;
  if (element->LineNumber().has_value()) return file + ":" + std::to_string(*element->LineNumber());
  return file;
}

Eigen::Isometry3d WorldPose(const SdfModelEntry& entry, const sdf::SemanticPose& pose,
                            const std::string& what, const std::string& where) {
  ignition::math::Pose3d resolved;
  const sdf::Errors errors = pose.Resolve(resolved, "__model__");
  if (!errors.empty()) {
    throw InputError(where + ": " + what + ": its pose cannot be resolved: \"" +
                     errors.front().Message() + "\"; check its relative_to frame");
  }
  return entry.X_WM * ToIsometry(resolved);
}

SdfLinkRef FindSdfLink(const SdfFile& file, const std::string& scoped_name) {
  const std::vector<SdfModelEntry>& models = file.models();
  for (size_t m = 0; m < models.size(); ++m) {
    const std::string& prefix = models[m].prefix;
    if (scoped_name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string local = scoped_name.substr(prefix.size());
    if (local.find(kSdfScope) != std::string::npos) continue;  // a nested model's
    if (const sdf::Link* link = models[m].model->LinkByName(local); link != nullptr) {
      return {link, static_cast<int>(m)};
    }
  }
  return {};
}

Eigen::Isometry3d SdfLinkPose(const SdfFile& file, const std::string& scoped_name) {
  const SdfLinkRef ref = FindSdfLink(file, scoped_name);
  MBSTREAM_CHECK(ref.link != nullptr);
  return WorldPose(file.models()[ref.model], ref.link->SemanticPose(), "link '" + scoped_name + "'",
                   file.Where(ref.link->Element()));
}

SdfMeshes MeshesOf(const SdfFile& file) {
  SdfMeshes meshes;
  for (const SdfModelEntry& entry : file.models()) {
    for (uint64_t l = 0; l < entry.model->LinkCount(); ++l) {
      const sdf::Link& link = *entry.model->LinkByIndex(l);
      for (uint64_t v = 0; v < link.VisualCount(); ++v) {
        AddMesh(link.VisualByIndex(v)->Geom(), &meshes.visual);
      }
      for (uint64_t c = 0; c < link.CollisionCount(); ++c) {
        AddMesh(link.CollisionByIndex(c)->Geom(), &meshes.collision);
      }
    }
  }
  return meshes;
}

SdfMeshes ReadSdfMeshes(const std::string& text) {
  // Hostile text never reaches libsdformat (a flood of attributes takes it minutes).
  try {
    return MeshesOf(SdfFile(text, "model.sdf"));
  } catch (const InputError&) {
    return {};
  }
}

[[noreturn]] void ThrowSdfErrors(const std::string& source, const sdf::Errors& errors) {
  std::string message;
  for (const sdf::Error& error : errors) {
    if (!message.empty()) message += "\n";
    const bool in_file = error.FilePath().has_value() && IsFilePath(*error.FilePath());
    message += in_file ? *error.FilePath() : source;
    if (error.LineNumber().has_value()) message += ":" + std::to_string(*error.LineNumber());
    message += ": SDFormat: \"" + error.Message() + "\"";
  }
  throw InputError(message + "\nfix the model file (SDFormat 1.6 or later)");
}

}  // namespace mbstream::model_files
