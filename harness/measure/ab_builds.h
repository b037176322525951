// What `fx2d-bench ab --a X --b Y` names, turned into a loaded engine plugin: a plugin file, a
// build directory holding one, the word `worktree` (the checkout of the current directory,
// uncommitted changes included), any git revision of the current directory's repository, or the
// word `built-in` (this binary's own Fx2D, the plugin table linked into it: against this build's
// plugin file it measures what calling the same code in a loaded library costs).
//
// A revision is extracted (git archive) and built with the plugin project of the tree this binary
// was built from (harness/plugin/CMakeLists.txt, FX2D_ROOT = the extracted tree), or of the tree
// `ab --source` or FX2D_SOURCE names, for an installed binary that outlived its tree
// (plugin_source_tree), in Release with the flags this binary was configured with, then the extra
// --a-cmake/--b-cmake arguments. Builds are cached in
// ${XDG_CACHE_HOME:-$HOME/.cache}/fx2d-bench/ab/<full sha>-<hash>/, the hash covering the CMake
// arguments and the plugin sources, so the same request never builds twice; the worktree's build
// directory is kept and rebuilt incrementally each time.
//
// Invariants: both builds are resolved (resolve_plugin_build) before either is built, so a name
// that means nothing is refused before minutes of building; a cached build is used only when its
// `complete` stamp exists (a failed or killed build is started again from scratch); build output
// goes to the build's log file, progress to stderr; a failure is one InputError line naming the
// option, the revision and the log.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "engines/plugin_engine.h"

namespace fxbench {

struct PluginBuild {
  std::shared_ptr<const Plugin> plugin;
  // Which build this is, for result files and tables, e.g. "a1b2c3d (HEAD~1) -DFX2D_NATIVE=ON".
  std::string description;
  // The plugin file loaded: what anything else measuring this build (a count under valgrind)
  // must load, rather than guess from the cache. Empty for the built-in engine.
  std::string path;
};

enum class BuildKind { plugin_file, worktree, revision, built_in };

// `--a`/`--b` checked and resolved, nothing built yet.
struct ResolvedBuild {
  std::string option;  // "--a"
  std::string spec;    // as typed
  BuildKind kind = BuildKind::plugin_file;
  std::string path;        // plugin_file: the file or build directory; otherwise the repository's top level
  std::string sha;         // revision: the full commit
  std::vector<std::string> cmake_args;  // the user's extra CMake arguments, split (cmake_words)
  std::string source_tree;  // revision, worktree: the tree whose harness/plugin builds it
};

// The name of the build directory `ab` keeps for a plugin built with `cmake_arguments` from the
// plugin project at `project`: it changes with every argument, with the project's files, so that a
// change to the plugin itself never reuses an older build, and with where the project is, since
// CMake ties a build directory to the source directory it was first configured from and refuses
// another (two checkouts with the same plugin files, a git worktree of this one, must not share one).
std::string plugin_build_key(const std::vector<std::string>& cmake_arguments,
                             const std::filesystem::path& project);

// The words of extra CMake arguments `text`, given with `option` (e.g. "--a" for --a-cmake), as a
// shell splits them: whitespace separates words, single quotes keep what they hold as it is, double
// quotes too but for a backslash before a double quote or a backslash. So one argument may hold
// spaces: "-DCMAKE_CXX_FLAGS='-O2 -g'". Throws InputError, one line, on a quote never closed.
std::vector<std::string> cmake_words(const std::string& option, const std::string& text);

// `words` as a build's description shows them: a word that holds a space, or none, in single quotes,
// so that the description reads as the arguments it was given.
std::string cmake_text(const std::vector<std::string>& words);

// Resolves `spec`, given as `option` (e.g. "--a"), with extra CMake arguments `cmake_args`
// (cmake_words; only for a revision or `worktree`) and `source` (--source, "" when not
// given: plugin_source_tree). Builds nothing. Throws InputError.
ResolvedBuild resolve_plugin_build(const std::string& option, const std::string& spec, const std::string& cmake_args,
                                   const std::string& source);

// The Fx2D source tree whose harness/plugin project builds a revision or the worktree into a
// plugin: `source` (ab --source), else $FX2D_SOURCE, else `built_from` (the tree this binary was
// built from) while it still holds that project. Throws InputError, one line saying which tree is
// missing what and how to name one, when none does.
std::string plugin_source_tree(const std::string& source, const std::string& built_from);

// Builds `build` when needed and loads its plugin. Throws InputError.
PluginBuild prepare_plugin_build(const ResolvedBuild& build);

// Where revision builds are cached.
std::string ab_cache_directory();

}  // namespace fxbench
