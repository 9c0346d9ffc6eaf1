// zbrdf completion: shell completion scripts made from the command table (tools/cli/command.h):
// the commands, prior's actions and each one's flags, read with DescribeCommand without running
// any command. `cmake --install` installs the scripts (README.md, Install); the man pages are made
// from `zbrdf completion commands` (cmake/zbrdf_docs.cmake).
#include <iostream>
#include <sstream>

#include "basis/error.h"
#include "tools/cli/command.h"

namespace zbrdf::cli {
namespace {

std::vector<CommandDescription> DescribeAll() {
  std::vector<CommandDescription> out;
  for (const auto& [name, command] : CommandTable()) {
    for (CommandDescription& d : DescribeCommand(command)) out.push_back(std::move(d));
  }
  return out;
}

std::string Join(const std::vector<std::string>& words) {
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : " ") + w;
  return out;
}

std::vector<std::string> FlagNames(const CommandDescription& d) {
  std::vector<std::string> out;
  for (const auto& [name, help] : d.flags) out.push_back(name);
  return out;
}

// 'name:help' as one single-quoted item of zsh's _describe, on one line: a ' inside would end
// the quote, and an unescaped ':' in the name would end the name.
std::string ZshItem(const std::string& name, const std::string& help) {
  std::string out = "'";
  for (char c : name) out += c == ':' ? std::string("\\:") : std::string(1, c);
  out += ":";
  for (char c : help) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c == '\n' ? ' ' : c;
    }
  }
  return out + "'";
}

std::string BashScript(const std::vector<CommandDescription>& all) {
  std::vector<std::string> commands;
  for (const auto& d : all) {
    if (d.words.find(' ') == std::string::npos) commands.push_back(d.words);
  }
  std::ostringstream out;
  out << "# bash completion for zbrdf " << ZBRDF_VERSION
      << ", made by `zbrdf completion bash` from its command table.\n"
         "# bash-completion loads it from PREFIX/share/bash-completion/completions/zbrdf; or put\n"
         "# `source <(zbrdf completion bash)` in ~/.bashrc.\n"
         "_zbrdf() {\n"
         "  local cur=${COMP_WORDS[COMP_CWORD]} key=${COMP_WORDS[1]} flags=\n"
         "  COMPREPLY=()\n"
         "  if ((COMP_CWORD == 1)); then\n"
         "    COMPREPLY=($(compgen -W '"
      << Join(commands)
      << " --help --version' -- \"$cur\"))\n"
         "    return 0\n"
         "  fi\n"
         "  case $key in\n";
  for (const auto& [name, command] : CommandTable()) {
    if (command.actions.empty()) continue;
    std::vector<std::string> actions;
    for (const Action& a : command.actions) actions.push_back(a.name);
    out << "    '" << name
        << "')\n"
           "      if ((COMP_CWORD == 2)); then\n"
           "        COMPREPLY=($(compgen -W '"
        << Join(actions)
        << " --help' -- \"$cur\"))\n"
           "        return 0\n"
           "      fi\n"
           "      key=\"$key ${COMP_WORDS[2]}\" ;;\n";
  }
  out << "  esac\n"
         "  # Anything but a flag (a value, a folder, a file) is left to the shell: -o default.\n"
         "  [[ $cur == -* ]] || return 0\n"
         "  case $key in\n";
  for (const auto& d : all) {
    out << "    '" << d.words << "') flags='" << Join(FlagNames(d)) << "' ;;\n";
  }
  out << "  esac\n"
         "  COMPREPLY=($(compgen -W \"$flags\" -- \"$cur\"))\n"
         "}\n"
         "complete -o default -F _zbrdf zbrdf\n";
  return out.str();
}

std::string ZshScript(const std::vector<CommandDescription>& all) {
  std::ostringstream out;
  out << "#compdef zbrdf\n"
         "# zsh completion for zbrdf "
      << ZBRDF_VERSION
      << ", made by `zbrdf completion zsh` from its command table.\n"
         "# zsh loads it as _zbrdf from a folder on its fpath (PREFIX/share/zsh/site-functions);\n"
         "# or put `source <(zbrdf completion zsh)` in ~/.zshrc, after compinit.\n"
         "_zbrdf() {\n"
         "  local -a choices\n"
         "  local key=${words[2]}\n"
         "  if ((CURRENT == 2)); then\n"
         "    choices=(\n";
  for (const auto& d : all) {
    if (d.words.find(' ') == std::string::npos) {
      out << "      " << ZshItem(d.words, d.summary) << "\n";
    }
  }
  out << "    )\n"
         "    _describe -t commands 'zbrdf command' choices\n"
         "    return\n"
         "  fi\n"
         "  case $key in\n";
  for (const auto& [name, command] : CommandTable()) {
    if (command.actions.empty()) continue;
    out << "    ('" << name
        << "')\n"
           "      if ((CURRENT == 3)); then\n"
           "        choices=(";
    for (size_t k = 0; k < command.actions.size(); ++k) {
      out << (k == 0 ? "" : " ") << ZshItem(command.actions[k].name, command.actions[k].summary);
    }
    out << ")\n"
           "        _describe -t actions 'zbrdf "
        << name
        << " action' choices\n"
           "        return\n"
           "      fi\n"
           "      key=\"$key ${words[3]}\" ;;\n";
  }
  out << "  esac\n"
         "  if [[ $PREFIX != -* ]]; then\n"
         "    _files\n"
         "    return\n"
         "  fi\n"
         "  case $key in\n";
  for (const auto& d : all) {
    out << "    ('" << d.words << "')\n      choices=(\n";
    for (const auto& [name, help] : d.flags) out << "        " << ZshItem(name, help) << "\n";
    out << "      ) ;;\n";
  }
  out << "  esac\n"
         "  _describe -t options 'zbrdf option' choices\n"
         "}\n"
         "# Autoloaded from the fpath: complete now; sourced: register.\n"
         "if [[ ${funcstack[1]} == _zbrdf ]]; then\n"
         "  _zbrdf \"$@\"\n"
         "else\n"
         "  compdef _zbrdf zbrdf\n"
         "fi\n";
  return out.str();
}

int RunCompletion(const std::vector<std::string>& args) {
  CommandLine cl("completion",
                 "Prints a shell completion script for zbrdf, made from its command table: the\n"
                 "commands, the actions of prior and every command's flags (where a value or a\n"
                 "file is expected, the shell completes file names).");
  cl.Positional("SHELL", "bash or zsh; or commands, a list for scripts (below)")
      .Epilog(
          "`zbrdf completion commands` prints each command and action (\"prior build\"), a tab\n"
          "and its summary, one per line: the man pages are made from it (README.md, Install).\n\n"
          "`cmake --install` puts the scripts where the shells look (README.md, Install):\n"
          "PREFIX/share/bash-completion/completions/zbrdf (loaded by bash-completion) and\n"
          "PREFIX/share/zsh/site-functions/_zbrdf (zsh, when that folder is on its fpath).\n"
          "Without installing them:\n"
          "  source <(zbrdf completion bash)    # in ~/.bashrc\n"
          "  source <(zbrdf completion zsh)     # in ~/.zshrc, after compinit");
  if (!cl.Parse(args)) return 0;
  const std::string shell = cl.Positional(0);
  if (shell != "bash" && shell != "zsh" && shell != "commands") {
    throw InputError("SHELL must be bash, zsh or commands (got '" + shell + "')");
  }
  const std::vector<CommandDescription> all = DescribeAll();
  if (shell == "bash") {
    std::cout << BashScript(all);
  } else if (shell == "zsh") {
    std::cout << ZshScript(all);
  } else {
    for (const auto& d : all) std::cout << d.words << "\t" << d.summary << "\n";
  }
  return 0;
}

const CommandRegistration kCompletionCommand({"completion", "print a bash or zsh completion script",
                                              RunCompletion});

}  // namespace
}  // namespace zbrdf::cli
