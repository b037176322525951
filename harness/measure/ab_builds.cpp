// Plugin files, build directories, the worktree and git revisions as loaded plugins; the cache
// layout and its invariants are in ab_builds.h.
#include "measure/ab_builds.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <thread>
#include <vector>

#include "common/child_process.h"
#include "common/errors.h"
#include "common/hash.h"

namespace fxbench {
namespace {

namespace fs = std::filesystem;

constexpr const char* plugin_file_name = "libfx2d_bench_plugin.so";
constexpr const char* worktree_word = "worktree";
constexpr const char* built_in_word = "built-in";

// --- child processes ------------------------------------------------------------------------------

// Runs argv (argv[0] looked up on PATH) with stdout and stderr sent to the file descriptors given.
// Returns true when it exited with status 0.
bool run_process(const std::vector<std::string>& argv, int stdout_fd, int stderr_fd) {
  return run_child(argv, {.in = -1, .out = stdout_fd, .err = stderr_fd}).exit_status == 0;
}

// The command's stdout, trimmed; nullopt when it fails. Its stderr is discarded.
std::optional<std::string> output_of(const std::vector<std::string>& argv) {
  const std::string capture = (fs::temp_directory_path() / ("fx2d-bench-ab." + std::to_string(getpid()))).string();
  const int out = open(capture.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  const int null = open("/dev/null", O_WRONLY | O_CLOEXEC);
  const bool ok = out >= 0 && null >= 0 && run_process(argv, out, null);
  if (out >= 0) close(out);
  if (null >= 0) close(null);
  std::ifstream file(capture);
  std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  fs::remove(capture);
  if (!ok) return std::nullopt;
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text;
}

// Appends the command line and then the command's output to `log`.
bool run_logged(const std::vector<std::string>& argv, const fs::path& log) {
  {
    std::ofstream line(log, std::ios::app);
    line << "$";
    for (const std::string& arg : argv) line << ' ' << arg;
    line << '\n';
  }
  const int fd = open(log.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  const bool ok = run_process(argv, fd, fd);
  close(fd);
  return ok;
}

// --- what a build is made of ----------------------------------------------------------------------

// The arguments this binary was configured with that decide how Fx2D is compiled, '|'-separated.
std::vector<std::string> same_flags_arguments() {
  std::vector<std::string> arguments;
  std::string list = FX2D_BENCH_AB_CMAKE_ARGS;
  for (std::size_t start = 0; start <= list.size();) {
    const std::size_t end = std::min(list.find('|', start), list.size());
    if (end > start) arguments.push_back(list.substr(start, end - start));
    start = end + 1;
  }
  return arguments;
}

std::string file_text(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

fs::path plugin_project(const fs::path& source_tree) { return source_tree / "harness" / "plugin"; }

}  // namespace

std::string plugin_build_key(const std::vector<std::string>& cmake_arguments, const fs::path& project) {
  Fnv1a64 hash;
  for (const std::string& argument : cmake_arguments) {
    hash.add(argument);
    hash.add(std::string_view("\0", 1));
  }
  hash.add(project.string());
  hash.add(std::string_view("\0", 1));
  for (const char* name :
       {"CMakeLists.txt", "Fx2dBenchPlugin.cmake", "fx2d_plugin.cpp", "fx2d_plugin_abi.h", "fx2d_bench_plugin.hpp"})
    hash.add(file_text(project / name));
  return hash.hex();
}

namespace {

std::string joined(const std::vector<std::string>& words) {
  std::string text;
  for (const std::string& word : words)
    if (!word.empty()) text += (text.empty() ? "" : " ") + word;
  return text;
}

struct BuildRequest {
  std::string option;                   // "--a"
  std::string spec;                     // as typed
  fs::path repository;                  // the git checkout the spec was resolved in
  fs::path source;                      // the tree to build
  fs::path project;                     // the plugin project that builds it (plugin_project)
  fs::path directory;                   // cache entry: build/, build.log, complete
  std::string plugin_description;       // compiled into the plugin
  std::vector<std::string> cmake_args;  // same flags, then the user's
};

// "--a" -> "A"
std::string side_of(const std::string& option) {
  std::string side = option.substr(2);
  for (char& c : side) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return side;
}

void progress_line(const std::string& text) { std::cerr << "fx2d-bench: " << text << '\n'; }

[[noreturn]] void build_failed(const BuildRequest& request, const std::string& stage) {
  throw InputError(request.option + " " + request.spec + ": " + stage + " failed; see " +
                   (request.directory / "build.log").string());
}

fs::path built_plugin(const BuildRequest& request) { return request.directory / "build" / plugin_file_name; }

// Whether `build` was configured with this plugin description. A worktree's names the HEAD it is
// of, which moves while its cache entry stays: configured once, the plugin went on calling itself
// "of" the HEAD of its first build.
bool configured_as(const fs::path& build, const std::string& description) {
  const fs::path cache = build / "CMakeCache.txt";
  return fs::exists(cache) && file_text(cache).find("\nFX2D_BENCH_PLUGIN_DESCRIPTION:STRING=" + description +
                                                    "\n") != std::string::npos;
}

void configure_and_build(const BuildRequest& request) {
  const fs::path log = request.directory / "build.log";
  const fs::path build = request.directory / "build";
  if (!configured_as(build, request.plugin_description)) {
    std::vector<std::string> configure = {FX2D_BENCH_CMAKE_COMMAND,
                                          "-S",
                                          request.project.string(),
                                          "-B",
                                          build.string(),
                                          "-DFX2D_ROOT=" + request.source.string(),
                                          "-DFX2D_BENCH_PLUGIN_DESCRIPTION=" + request.plugin_description};
    configure.insert(configure.end(), request.cmake_args.begin(), request.cmake_args.end());
    if (!run_logged(configure, log)) build_failed(request, "configuring the plugin build");
  }
  const std::string jobs = std::to_string(std::max(1u, std::thread::hardware_concurrency()));
  if (!run_logged({FX2D_BENCH_CMAKE_COMMAND, "--build", build.string(), "--target", "fx2d_bench_plugin", "-j", jobs}, log))
    build_failed(request, "building the plugin");
}

// A revision's tree is the revision's own files: git archive, not a checkout of this worktree.
void extract_revision(const BuildRequest& request, const std::string& sha) {
  const fs::path log = request.directory / "build.log";
  const fs::path archive = request.directory / "source.tar";
  fs::create_directories(request.source);
  if (!run_logged({"git", "-C", request.repository.string(), "archive", "--format=tar", "--output=" + archive.string(), sha}, log) ||
      !run_logged({"tar", "-xf", archive.string(), "-C", request.source.string()}, log))
    build_failed(request, "extracting the revision");
  fs::remove(archive);
}

PluginBuild loaded(const std::string& option, const fs::path& path, std::string description) {
  try {
    return {Plugin::load(path.string()), std::move(description), fs::absolute(path).string()};
  } catch (const InputError& error) {
    throw InputError(option + ": " + error.what());
  }
}

// --- the kinds of --a/--b that load a file -----------------------------------------------------

PluginBuild prebuilt(const std::string& option, const std::string& spec) {
  fs::path path = spec;
  if (fs::is_directory(path)) {
    const std::vector<fs::path> candidates = {path / plugin_file_name, path / "harness" / "plugin" / plugin_file_name};
    const auto found = std::ranges::find_if(candidates, [](const fs::path& p) { return fs::is_regular_file(p); });
    if (found == candidates.end())
      throw InputError(option + " " + spec + ": a directory without " + plugin_file_name +
                       " (looked in it and in its harness/plugin/); build the fx2d_bench_plugin target there");
    path = *found;
  }
  PluginBuild build = loaded(option, path, {});
  const std::string compiled = build.plugin->table().build_description();
  build.description = compiled.empty() ? spec : compiled + " (" + spec + ")";
  return build;
}

PluginBuild built_worktree(const ResolvedBuild& build, const std::vector<std::string>& cmake_args) {
  const fs::path checkout = build.path;
  const fs::path project = plugin_project(build.source_tree);
  const std::string head = output_of({"git", "-C", checkout.string(), "rev-parse", "--short", "HEAD"}).value_or("unknown");
  std::vector<std::string> key = cmake_args;
  key.emplace_back(checkout.string());
  const std::string description =
      joined({"worktree " + checkout.string() + " (of " + head + ")", cmake_text(build.cmake_args)});
  const fs::path directory = fs::path(ab_cache_directory()) / ("worktree-" + plugin_build_key(key, project));
  BuildRequest request{build.option, worktree_word, checkout, checkout, project, directory, description, cmake_args};
  fs::create_directories(request.directory);
  progress_line(side_of(build.option) + " = " + description + ": building (log " + (request.directory / "build.log").string() + ")");
  configure_and_build(request);
  return loaded(build.option, built_plugin(request), description);
}

PluginBuild built_revision(const ResolvedBuild& build, const std::vector<std::string>& cmake_args) {
  const std::string& option = build.option;
  const std::string& spec = build.spec;
  const std::string& sha = build.sha;
  const std::string short_sha = sha.substr(0, 7);
  const std::string description = joined(
      {spec.starts_with(short_sha) ? short_sha : short_sha + " (" + spec + ")", cmake_text(build.cmake_args)});
  const fs::path project = plugin_project(build.source_tree);
  const fs::path directory =
      fs::path(ab_cache_directory()) / (sha + "-" + plugin_build_key(cmake_args, project));
  const std::string plugin_description = joined({short_sha, cmake_text(build.cmake_args)});
  BuildRequest request{option, spec, build.path, directory / "src", project, directory, plugin_description, cmake_args};
  const std::string side = side_of(option);
  if (fs::exists(directory / "complete") && fs::exists(built_plugin(request))) {
    progress_line(side + " = " + description + ": cached build " + directory.string());
    return loaded(option, built_plugin(request), description);
  }
  fs::remove_all(directory);
  fs::create_directories(directory);
  progress_line(side + " = " + description + ": building (log " + (directory / "build.log").string() + ")");
  extract_revision(request, sha);
  configure_and_build(request);
  std::ofstream(directory / "complete") << sha << '\n';
  return loaded(option, built_plugin(request), description);
}

}  // namespace

std::vector<std::string> cmake_words(const std::string& option, const std::string& text) {
  std::vector<std::string> words;
  std::string word;
  bool in_word = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == ' ' || c == '\t' || c == '\n') {
      if (in_word) words.push_back(word);
      word.clear();
      in_word = false;
      continue;
    }
    in_word = true;
    if (c != '\'' && c != '"') {
      word += c;
      continue;
    }
    const std::size_t opened = i;
    for (++i; i < text.size() && text[i] != c; ++i) {
      // Within double quotes a backslash keeps the quote or backslash after it.
      if (c == '"' && text[i] == '\\' && i + 1 < text.size() && (text[i + 1] == '"' || text[i + 1] == '\\'))
        ++i;
      word += text[i];
    }
    if (i == text.size())
      throw InputError(option + "-cmake: the quote at character " + std::to_string(opened + 1) + " of `" +
                       text + "` is never closed; expected a matching " + std::string(1, c));
  }
  if (in_word) words.push_back(word);
  return words;
}

std::string cmake_text(const std::vector<std::string>& words) {
  std::vector<std::string> shown;
  for (const std::string& word : words) {
    const bool quoted = word.empty() || word.find_first_of(" \t\n") != std::string::npos;
    shown.push_back(quoted ? "'" + word + "'" : word);
  }
  return joined(shown);
}

std::string ab_cache_directory() {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const char* home = std::getenv("HOME");
  const fs::path base = xdg != nullptr && *xdg != '\0' ? fs::path(xdg)
                        : home != nullptr && *home != '\0' ? fs::path(home) / ".cache"
                                                           : fs::temp_directory_path();
  return (base / "fx2d-bench" / "ab").string();
}

// The top level of the git checkout holding the current directory: where `worktree` and revisions
// are looked up, so that `ab` measures the checkout it runs in, not the one this binary came from.
fs::path current_checkout(const std::string& option, const std::string& spec) {
  const std::optional<std::string> top = output_of({"git", "rev-parse", "--show-toplevel"});
  if (!top || top->empty())
    throw InputError(option + " " + spec + ": the current directory " + fs::current_path().string() +
                     " is not in a git checkout; run ab from the Fx2D checkout to measure, or name a plugin file");
  if (!fs::exists(fs::path(*top) / "fx2d" / "include" / "fx2d" / "fx2d.h"))
    throw InputError(option + " " + spec + ": " + *top + " is not an Fx2D checkout (no fx2d/include/fx2d/fx2d.h)");
  return *top;
}

std::string plugin_source_tree(const std::string& source, const std::string& built_from) {
  const auto holds_plugin_project = [](const fs::path& tree) {
    return fs::is_regular_file(plugin_project(tree) / "CMakeLists.txt");
  };
  const char* environment = std::getenv("FX2D_SOURCE");
  const bool from_environment = source.empty() && environment != nullptr && *environment != '\0';
  if (!source.empty() || from_environment) {
    const std::string tree = from_environment ? environment : source;
    if (!holds_plugin_project(tree))
      throw InputError((from_environment ? "FX2D_SOURCE=" : "--source ") + tree +
                       ": not an Fx2D source tree (no harness/plugin/CMakeLists.txt)");
    return fs::absolute(tree).lexically_normal().string();
  }
  if (!holds_plugin_project(built_from))
    throw InputError("building a revision or the worktree takes the harness/plugin project of an Fx2D source tree, and " +
                     built_from + ", which this fx2d-bench was built from, has none; name one with --source DIR or "
                     "FX2D_SOURCE");
  return built_from;
}

ResolvedBuild resolve_plugin_build(const std::string& option, const std::string& spec, const std::string& cmake_args,
                                   const std::string& source) {
  ResolvedBuild build{option, spec, BuildKind::plugin_file, spec, {}, cmake_words(option, cmake_args), {}};
  const bool is_built_in = spec == built_in_word;
  if (is_built_in || (spec != worktree_word && fs::exists(spec))) {
    if (!build.cmake_args.empty())
      throw InputError(option + "-cmake: applies to a git revision or worktree, not to the " +
                       (is_built_in ? std::string("built-in engine") : "prebuilt plugin " + spec));
    if (is_built_in) build.kind = BuildKind::built_in;
    return build;
  }
  const bool is_revision = spec != worktree_word;
  build.path = current_checkout(option, spec).string();
  build.kind = is_revision ? BuildKind::revision : BuildKind::worktree;
  if (is_revision) {
    const std::optional<std::string> sha =
        output_of({"git", "-C", build.path, "rev-parse", "--verify", "--quiet", spec + "^{commit}"});
    if (!sha || sha->size() < 7)
      throw InputError(option + " " + spec + ": not a plugin file, a build directory, `worktree`, `built-in`, nor a " +
                       "git revision of " + build.path);
    build.sha = *sha;
  }
  try {
    build.source_tree = plugin_source_tree(source, FX2D_SOURCE_DIR);
  } catch (const InputError& missing) {
    throw InputError(option + " " + spec + ": " + missing.what());
  }
  return build;
}

PluginBuild prepare_plugin_build(const ResolvedBuild& build) {
  if (build.kind == BuildKind::plugin_file) return prebuilt(build.option, build.spec);
  if (build.kind == BuildKind::built_in) return {linked_fx2d_plugin(), built_in_word, {}};
  std::vector<std::string> all_args = same_flags_arguments();
  all_args.insert(all_args.end(), build.cmake_args.begin(), build.cmake_args.end());
  if (build.kind == BuildKind::worktree) return built_worktree(build, all_args);
  return built_revision(build, all_args);
}

}  // namespace fxbench
