// The zbrdf CLI's subcommand table and argument parser.
//
// Each tools/cli/<name>.cc defines one subcommand and registers it with a file-scope
// `const CommandRegistration k<Name>Command{...}` object (a name of its own: the
// subcommands compile eight to a unity batch), so adding a subcommand touches no shared table.
// A subcommand is a thin function over the libraries: it parses flags with CommandLine, calls
// library code, and prints a human-readable summary or, with --json, one JSON object. It parses
// before it does anything else: --help, the completion scripts (DescribeCommand) and the man
// pages made from --help read a command's flags by running it up to Parse.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace zbrdf::cli {

// Declarative flag parser. Flags are `--name value` or `--name=value`; booleans are `--name`.
// Parse() rejects unknown flags, missing values and missing positionals with InputError naming
// the flag and pointing at --help. Typed getters validate and name the flag on bad input.
class CommandLine {
 public:
  CommandLine(std::string command, std::string summary);

  CommandLine& Positional(const std::string& name, const std::string& help, bool required = true);
  CommandLine& Flag(const std::string& name, const std::string& help);
  CommandLine& Option(const std::string& name, const std::string& value_name,
                      const std::string& help, std::optional<std::string> default_value = {});
  // Free text printed after the option list (examples, notes).
  CommandLine& Epilog(const std::string& text);

  // Returns false if --help was given (the help has been printed to stdout), or, printing
  // nothing, when the command is being described (DescribeCommand below). An unknown flag's
  // error names the declared flags closest to it ("did you mean --order?").
  bool Parse(const std::vector<std::string>& args);

  bool Has(const std::string& name) const;  // flag given, or option given or defaulted
  std::string Get(const std::string& name) const;
  double GetDouble(const std::string& name) const;
  double GetDouble(const std::string& name, double min, double max) const;
  int GetInt(const std::string& name, int min, int max) const;
  // "a,b" -> {a, b} with exactly `count` numbers.
  std::vector<double> GetDoubles(const std::string& name, size_t count) const;
  // "a,b" -> {"a", "b"}, items trimmed; an empty item is an error naming the flag.
  std::vector<std::string> GetList(const std::string& name) const;
  std::string Positional(size_t index) const;
  size_t NumPositionals() const { return positional_values_.size(); }

  std::string Help() const;
  // The flags and options declared, in order (--help first): "--name" and its help.
  std::vector<std::pair<std::string, std::string>> Flags() const;

 private:
  struct Spec {
    std::string name, value_name, help;
    bool is_flag = false;
    std::optional<std::string> default_value;
  };
  std::string command_, summary_, epilog_;
  std::vector<Spec> options_;
  std::vector<std::pair<std::string, std::string>> positionals_;  // name, help
  size_t required_positionals_ = 0;
  std::map<std::string, std::string> values_;
  std::vector<std::string> positional_values_;
};

// A word a command dispatches on before parsing, each with a CommandLine of its own
// (`zbrdf prior build`, `zbrdf prior info`).
struct Action {
  std::string name;
  std::string summary;  // one line, as in the command's usage
};

struct Command {
  std::string name;
  std::string summary;
  std::function<int(const std::vector<std::string>& args)> run;  // returns the exit code
  std::vector<Action> actions = {};  // empty: run parses all its arguments with one CommandLine
};

std::map<std::string, Command>& CommandTable();

// A command or action as completion scripts and man pages need it.
struct CommandDescription {
  std::string words;    // "simulate", or "prior build" for an action
  std::string summary;  // one line
  std::vector<std::pair<std::string, std::string>> flags;  // "--name", help; --help first
};

// Describes a command without running it: calls its run function in describe mode, where the
// first CommandLine::Parse records the declared flags and returns false, so that the function
// returns before it acts, as it does for --help (every command parses its arguments before
// anything else; --help and the man pages rely on that too). A command with actions is run
// once per action (args {action}); the command itself then has only --help. Returns the command
// and then its actions. Throws std::logic_error if a run function returned without parsing.
std::vector<CommandDescription> DescribeCommand(const Command& command);

struct CommandRegistration {
  explicit CommandRegistration(Command command);
};

// zbrdf's main(): runs the subcommand argv[1] with the rest of argv (`--version` and `-V` are
// `version`; a mistyped command gets the closest names), prints errors, and returns
// the exit status: the command's own (0 done, 130 interrupted), 2 for bad input (flags, files,
// sessions; also a full disk or a session another process writes), 3 for a device error, 4 for a
// numerical failure, 1 otherwise. First it sets the allocator to keep freed memory for reuse
// (basis/freed_memory.h), as the test binaries' main() does.
int RunZbrdf(int argc, char** argv);

}  // namespace zbrdf::cli
