#include "fleetnav/ctl/completion.hpp"

#include <algorithm>
#include <sstream>
#include <vector>

#include "absl/strings/str_join.h"

namespace fleetnav::ctl {
namespace {

/// The long flags of `app` (--name), help included.
std::vector<std::string> LongFlags(const CLI::App& app) {
  std::vector<std::string> flags;
  for (const CLI::Option* option : app.get_options()) {
    for (const std::string& name : option->get_lnames()) flags.push_back("--" + name);
  }
  return flags;
}

/// One `case` arm per level: the path of subcommands (" map import") and what may follow it.
void AddLevels(const CLI::App& app, const std::string& path, std::vector<std::string>* paths,
               std::ostringstream* arms, const std::vector<std::string>& global_flags) {
  std::vector<std::string> words;
  for (const CLI::App* sub : app.get_subcommands({})) {
    words.push_back(sub->get_name());
    paths->push_back(path + " " + sub->get_name());
  }
  std::vector<std::string> flags = LongFlags(app);
  if (!path.empty()) flags.insert(flags.end(), global_flags.begin(), global_flags.end());
  for (const std::string& flag : flags) {
    // A level's own flag of a global flag's name (map export --version) is offered once.
    if (std::find(words.begin(), words.end(), flag) == words.end()) words.push_back(flag);
  }
  *arms << "    \"" << path << "\") words=\"" << absl::StrJoin(words, " ") << "\" ;;\n";
  for (const CLI::App* sub : app.get_subcommands({})) {
    AddLevels(*sub, path + " " + sub->get_name(), paths, arms, global_flags);
  }
}

}  // namespace

std::string BashCompletionScript(const CLI::App& app, const std::string& program) {
  std::vector<std::string> paths;
  std::ostringstream arms;
  std::vector<std::string> global_flags = LongFlags(app);
  AddLevels(app, "", &paths, &arms, global_flags);
  std::vector<std::string> quoted;
  for (const std::string& path : paths) quoted.push_back("\"" + path + "\"");
  const std::string function = "_" + program;
  std::ostringstream script;
  script << "# bash completion for " << program << " (made by `" << program
         << " completion bash`)\n"
         << function << "() {\n"
         << "  local cur=${COMP_WORDS[COMP_CWORD]} path=\"\" word i words=\"\"\n"
         << "  for ((i = 1; i < COMP_CWORD; i++)); do\n"
         << "    word=${COMP_WORDS[i]}\n"
         << "    [[ $word == -* ]] && continue\n"
         << "    case \"$path $word\" in\n"
         << "      " << absl::StrJoin(quoted, "|") << ") path=\"$path $word\" ;;\n"
         << "    esac\n"
         << "  done\n"
         << "  case \"$path\" in\n"
         << arms.str() << "  esac\n"
         << "  COMPREPLY=($(compgen -W \"$words\" -- \"$cur\"))\n"
         << "}\n"
         << "complete -F " << function << " " << program << "\n";
  return script.str();
}

}  // namespace fleetnav::ctl
