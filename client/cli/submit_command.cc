// `mbstream submit MODEL.urdf|MODEL.sdf|WORLD.sdf|DIR [--scene FILE] [--asset FILE]...
//  [--package-path DIR]... [--with-collision] [--name NAME] [--repair] [--couple-mimic]
//  [--floating-base]`
#include <iostream>

#include "client/cli/model_flags.h"
#include "client/cli/server_commands.h"
#include "server/wire/model_bundle_files.h"
#include "shared/common/check.h"

namespace mbstream::cli {

namespace {

struct SubmitOptions {
  BundleFiles files;
  bool repair = false;
  bool couple_mimic = false;
  bool floating_base = false;
};

int Submit(const ClientOptions& client, const SubmitOptions& options) {
  v1::SubmitModelRequest request;
  BundleRead read = ReadModelBundle(options.files);
  for (const std::string& warning : read.warnings) std::cerr << "warning: " << warning << "\n";
  *request.mutable_bundle() = std::move(read.bundle);
  request.mutable_bundle()->set_repair(options.repair);
  request.mutable_bundle()->set_couple_mimic(options.couple_mimic);
  request.mutable_bundle()->set_floating_base(options.floating_base);
  grpc::ClientContext context;
  v1::ModelInfo info;
  const grpc::Status status = ConnectSimulation(client)->SubmitModel(&context, request, &info);
  if (!status.ok()) return ReportRpcError("submit", client, status);
  std::cout << info.id() << "\n";
  std::cerr << "model '" << info.name() << "': " << info.dofs() << " joints, " << info.links()
            << " links, " << info.total_mass_kg() << " kg, TCP "
            << (info.tcp_frame().empty() ? "none" : info.tcp_frame()) << ", scene "
            << (info.has_scene() ? "yes" : "no") << ", " << info.num_assets() << " assets\n";
  for (const std::string& warning : info.warnings()) std::cerr << "warning: " << warning << "\n";
  if (!options.files.name.empty() && info.name() != options.files.name) {
    // A model is stored once per content: the same files submitted again are the model
    // already there, under the name it was first given.
    std::cerr << "note: --name '" << options.files.name << "' not applied: the content is that of "
              << "model " << info.id() << ", already there as '" << info.name()
              << "'; run it by that name or id (or change the files to submit a new model)\n";
  }
  return 0;
}

}  // namespace

void AddSubmitCommand(CLI::App& app, std::shared_ptr<const ClientOptions> client, int* exit_code) {
  auto options = std::make_shared<SubmitOptions>();
  CLI::App* command =
      app.add_subcommand("submit", "compile and store a model on the server; prints its id");
  command
      ->add_option("model", options->files.model_path,
                   "URDF or SDFormat file (told apart by content), or a model directory (one "
                   ".urdf or .sdf, its .scene), or a world's directory (its world .sdf and the "
                   "models it includes); the meshes they refer to are found and attached, "
                   "with the files those name (an OBJ's .mtl and images, a Collada's images); "
                   "a world's <include>s are sent written into it")
      ->required()
      ->check(CLI::ExistingPath);
  command->add_option("--scene", options->files.scene_path, "scene script for viewers")
      ->check(CLI::ExistingFile);
  command
      ->add_option("--asset", options->files.asset_paths,
                   "a mesh file the model file or scene uses")
      ->check(CLI::ExistingFile);
  command
      ->add_option("--package-path", options->files.package_paths,
                   "a folder searched for the ROS packages of package:// meshes and the models "
                   "of model:// meshes and includes (before $MBSTREAM_PACKAGE_PATH, colon "
                   "separated)")
      ->check(CLI::ExistingDirectory);
  command->add_flag(
      "--with-collision", options->files.with_collision,
      "attach the collision meshes too (contact takes their convex hulls; without them "
      "mesh collisions touch nothing)");
  command->add_option("--name", options->files.name,
                      "display name (default: the URDF's robot name, the SDFormat model's name)");
  command->add_flag("--repair", options->repair, kRepairHelp);
  command->add_flag("--couple-mimic", options->couple_mimic, kCoupleMimicHelp);
  command->add_flag("--floating-base", options->floating_base, kFloatingBaseHelp);
  command->callback([client, options, exit_code] {
    try {
      *exit_code = Submit(*client, *options);
    } catch (const InputError& error) {
      std::cerr << "mbstream submit: " << error.what() << "\n";
      *exit_code = 2;
    }
  });
}

}  // namespace mbstream::cli
