#include "tools/cli/command.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "basis/error.h"
#include "basis/freed_memory.h"
#include "basis/strings.h"

namespace zbrdf::cli {
namespace {

// Set by DescribeCommand while a command's run function runs: Parse records its CommandLine here.
thread_local std::optional<CommandLine>* described = nullptr;

// "'a'", "'a' or 'b'", ... (quote: "'" or "" for flags written as --name).
std::string OrList(const std::vector<std::string>& names, const std::string& quote) {
  std::string out;
  for (size_t k = 0; k < names.size(); ++k) {
    out += (k == 0 ? "" : " or ") + quote + names[k] + quote;
  }
  return out;
}

}  // namespace

CommandLine::CommandLine(std::string command, std::string summary)
    : command_(std::move(command)), summary_(std::move(summary)) {
  Flag("help", "print this help and exit");
}

CommandLine& CommandLine::Positional(const std::string& name, const std::string& help,
                                     bool required) {
  positionals_.emplace_back(name, help);
  if (required) required_positionals_ = positionals_.size();
  return *this;
}

CommandLine& CommandLine::Flag(const std::string& name, const std::string& help) {
  options_.push_back({name, "", help, true, std::nullopt});
  return *this;
}

CommandLine& CommandLine::Option(const std::string& name, const std::string& value_name,
                                 const std::string& help,
                                 std::optional<std::string> default_value) {
  options_.push_back({name, value_name, help, false, std::move(default_value)});
  return *this;
}

CommandLine& CommandLine::Epilog(const std::string& text) {
  epilog_ = text;
  return *this;
}

bool CommandLine::Parse(const std::vector<std::string>& args) {
  if (described != nullptr) {
    described->emplace(*this);
    return false;
  }
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg.rfind("--", 0) == 0 && arg.size() > 2) {
      std::string name = arg.substr(2);
      std::optional<std::string> inline_value;
      if (const size_t eq = name.find('='); eq != std::string::npos) {
        inline_value = name.substr(eq + 1);
        name = name.substr(0, eq);
      }
      const Spec* spec = nullptr;
      for (const Spec& s : options_) {
        if (s.name == name) spec = &s;
      }
      if (spec == nullptr) {
        std::vector<std::string> declared;
        for (const Spec& s : options_) declared.push_back("--" + s.name);
        const std::vector<std::string> close = ClosestNames("--" + name, declared);
        throw InputError("unknown flag --" + name +
                         (close.empty() ? "" : "; did you mean " + OrList(close, "") + "?") +
                         " (see zbrdf " + command_ + " --help)");
      }
      if (spec->is_flag) {
        if (inline_value) {
          throw InputError("--" + name + " takes no value");
        }
        values_.insert_or_assign(name, std::string(1, '1'));
      } else if (inline_value) {
        values_[name] = *inline_value;
      } else {
        if (i + 1 >= args.size()) {
          throw InputError("--" + name + " needs a value (" +
                           spec->value_name + ")");
        }
        values_[name] = args[++i];
      }
    } else {
      positional_values_.push_back(arg);
    }
  }
  if (values_.count("help")) {
    std::cout << Help();
    return false;
  }
  if (positional_values_.size() < required_positionals_) {
    throw InputError("missing " +
                     positionals_[positional_values_.size()].first + " (see zbrdf " + command_ +
                     " --help)");
  }
  if (positional_values_.size() > positionals_.size()) {
    throw InputError("unexpected argument '" +
                     positional_values_[positionals_.size()] + "' (see zbrdf " + command_ +
                     " --help)");
  }
  for (const Spec& s : options_) {
    if (!s.is_flag && s.default_value && !values_.count(s.name)) values_[s.name] = *s.default_value;
  }
  return true;
}

bool CommandLine::Has(const std::string& name) const { return values_.count(name) > 0; }

std::string CommandLine::Get(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) {
    throw InputError("--" + name + " is required (see zbrdf " +
                     command_ + " --help)");
  }
  return it->second;
}

namespace {
double ParseNumber(const std::string& text, const std::string& what) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v)) {
    throw InputError(what + ": '" + text + "' is not a finite number");
  }
  return v;
}
}  // namespace

double CommandLine::GetDouble(const std::string& name) const {
  return ParseNumber(Get(name), "--" + name);
}

double CommandLine::GetDouble(const std::string& name, double min, double max) const {
  const double v = GetDouble(name);
  if (v < min || v > max) {
    std::ostringstream msg;
    msg << "--" << name << " must be in [" << min << ", " << max
        << "] (got " << Get(name) << ")";
    throw InputError(msg.str());
  }
  return v;
}

int CommandLine::GetInt(const std::string& name, int min, int max) const {
  const double v = GetDouble(name);
  if (v != std::floor(v) || v < min || v > max) {
    std::ostringstream msg;
    msg << "--" << name << " must be an integer in [" << min << ", "
        << max << "] (got " << Get(name) << ")";
    throw InputError(msg.str());
  }
  return static_cast<int>(v);
}

std::vector<double> CommandLine::GetDoubles(const std::string& name, size_t count) const {
  const std::string text = Get(name);
  std::vector<double> out;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    out.push_back(ParseNumber(item, "--" + name));
  }
  if (out.size() != count) {
    throw InputError("--" + name + " needs " + std::to_string(count) +
                     " comma-separated numbers (got '" + text + "')");
  }
  return out;
}

std::vector<std::string> CommandLine::GetList(const std::string& name) const {
  std::vector<std::string> out;
  std::stringstream ss(Get(name));
  std::string item;
  while (std::getline(ss, item, ',')) {
    const size_t b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
    if (b == std::string::npos) {
      throw InputError("--" + name + " has an empty item (got '" + Get(name) +
                       "'); separate names by single commas");
    }
    out.push_back(item.substr(b, e - b + 1));
  }
  return out;
}

std::string CommandLine::Positional(size_t index) const {
  if (index >= positional_values_.size()) {
    throw InputError("missing " + positionals_.at(index).first);
  }
  return positional_values_[index];
}

std::string CommandLine::Help() const {
  std::ostringstream out;
  out << "Usage: zbrdf " << command_;
  for (size_t i = 0; i < positionals_.size(); ++i) {
    out << (i < required_positionals_ ? " " : " [") << positionals_[i].first
        << (i < required_positionals_ ? "" : "]");
  }
  out << " [options]\n\n" << summary_ << "\n";
  if (!positionals_.empty()) {
    out << "\nArguments:\n";
    for (const auto& [name, help] : positionals_) {
      out << "  " << name << std::string(name.size() < 24 ? 24 - name.size() : 1, ' ') << help
          << "\n";
    }
  }
  out << "\nOptions:\n";
  for (const Spec& s : options_) {
    std::string left = "--" + s.name + (s.is_flag ? "" : " " + s.value_name);
    out << "  " << left << std::string(left.size() < 24 ? 24 - left.size() : 1, ' ') << s.help;
    if (s.default_value) out << " (default: " << *s.default_value << ")";
    out << "\n";
  }
  if (!epilog_.empty()) out << "\n" << epilog_ << (epilog_.back() == '\n' ? "" : "\n");
  return out.str();
}

std::vector<std::pair<std::string, std::string>> CommandLine::Flags() const {
  std::vector<std::pair<std::string, std::string>> out;
  for (const Spec& s : options_) out.emplace_back("--" + s.name, s.help);
  return out;
}

std::map<std::string, Command>& CommandTable() {
  static std::map<std::string, Command> table;
  return table;
}

CommandRegistration::CommandRegistration(Command command) {
  CommandTable()[command.name] = std::move(command);
}

namespace {

CommandDescription DescribeRun(const Command& command, const std::vector<std::string>& args,
                               const std::string& words, const std::string& summary) {
  std::optional<CommandLine> cl;
  described = &cl;
  struct Reset {
    ~Reset() { described = nullptr; }
  } reset;
  command.run(args);
  if (!cl) {
    throw std::logic_error("zbrdf " + words +
                           " returned without parsing its arguments; a command must parse them "
                           "with CommandLine::Parse before it acts (tools/cli/command.h)");
  }
  return {words, summary, cl->Flags()};
}

}  // namespace

std::vector<CommandDescription> DescribeCommand(const Command& command) {
  if (command.actions.empty()) {
    return {DescribeRun(command, {}, command.name, command.summary)};
  }
  std::vector<CommandDescription> out = {
      {command.name, command.summary, {{"--help", "print this help and exit"}}}};
  for (const Action& action : command.actions) {
    out.push_back(DescribeRun(command, {action.name}, command.name + " " + action.name,
                              action.summary));
  }
  return out;
}

namespace {

void PrintUsage() {
  std::cout << "Usage: zbrdf <command> [options]\n\n"
               "Measure, simulate, fit and export BRDFs captured with zonal basis "
               "illumination.\nzbrdf <command> --help explains each command.\n\nCommands:\n";
  for (const auto& [name, command] : CommandTable()) {
    std::cout << "  " << name << std::string(name.size() < 16 ? 16 - name.size() : 1, ' ')
              << command.summary << "\n";
  }
  std::cout << "\nOptions:\n"
               "  -h, --help      print this help and exit\n"
               "  -V, --version   print the version (as zbrdf version) and exit\n"
               "\nzbrdf completion --help says how to set up completion in bash and zsh. "
               "Installed with its\nmanual pages (README.md, Install), each command has one: "
               "man zbrdf-<command>.\n";
}

}  // namespace

int RunZbrdf(int argc, char** argv) {
  KeepFreedMemoryForReuse();  // fewer page faults for the same work (basis/freed_memory.h)
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h" ||
      std::string(argv[1]) == "help") {
    PrintUsage();
    return argc < 2 ? 2 : 0;
  }
  // --version and -V are the version command (GNU's convention; help2man asks for --version).
  const std::string name =
      std::string(argv[1]) == "--version" || std::string(argv[1]) == "-V" ? "version" : argv[1];
  auto& table = CommandTable();
  auto it = table.find(name);
  if (it == table.end()) {
    std::vector<std::string> known = {"--help", "--version"};
    if (name.rfind('-', 0) != 0) {
      known.clear();
      for (const auto& [command_name, command] : table) known.push_back(command_name);
    }
    const std::vector<std::string> close = ClosestNames(name, known);
    std::cerr << "zbrdf: unknown " << (name.rfind('-', 0) == 0 ? "option" : "command") << " '"
              << name << "'" << (close.empty() ? "" : "; did you mean " + OrList(close, "'") + "?")
              << " (zbrdf --help lists them)\n";
    return 2;
  }
  std::vector<std::string> args(argv + 2, argv + argc);
  try {
    return it->second.run(args);
  } catch (const InputError& e) {
    std::cerr << "zbrdf " << name << ": error: " << e.what() << "\n";
    return 2;
  } catch (const DeviceError& e) {
    std::cerr << "zbrdf " << name << ": device error: " << e.what() << "\n";
    return 3;
  } catch (const NumericalError& e) {
    std::cerr << "zbrdf " << name << ": numerical failure: " << e.what() << "\n";
    return 4;
  } catch (const std::exception& e) {
    std::cerr << "zbrdf " << name << ": error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace zbrdf::cli
