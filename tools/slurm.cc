#include "tools/slurm.h"

#include <fcntl.h>
#include <poll.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include <yaml-cpp/yaml.h>

#include "basis/atomic_file.h"
#include "basis/data_path.h"
#include "basis/error.h"
#include "tools/json_file.h"

extern char** environ;

namespace zbrdf {
namespace fs = std::filesystem;
namespace {

struct SlurmCommandResult {
  int status = -1;  // exit status, or -1 when it could not start or was killed
  std::string output;  // stdout and stderr together
};

// Runs argv[0] (found on PATH) with the environment of this process; waits for it.
SlurmCommandResult RunProcess(const std::vector<std::string>& argv) {
  SlurmCommandResult result;
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) return result;
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 1);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 2);
  std::vector<char*> args;
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  pid_t pid = -1;
  const int spawned = ::posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipe_fds[1]);
  if (spawned != 0) {
    ::close(pipe_fds[0]);
    result.output = std::string(argv[0]) + ": " + std::strerror(spawned);
    return result;
  }
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(pipe_fds[0], buffer, sizeof(buffer));
    if (n > 0) {
      result.output.append(buffer, static_cast<size_t>(n));
    } else if (n < 0 && errno == EINTR) {
      continue;
    } else {
      break;
    }
  }
  ::close(pipe_fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return result;
}

std::string Trim(std::string s) {
  s.erase(0, s.find_first_not_of(" \t\r\n"));
  s.erase(s.find_last_not_of(" \t\r\n") + 1);
  return s;
}

// sbatch --parsable prints "jobid" or "jobid;cluster".
std::string SubmitScript(const std::vector<std::string>& sbatch_args) {
  std::vector<std::string> argv = {"sbatch", "--parsable"};
  argv.insert(argv.end(), sbatch_args.begin(), sbatch_args.end());
  const SlurmCommandResult r = RunProcess(argv);
  std::string out = Trim(r.output);
  if (r.status != 0) {
    std::string command;
    for (const std::string& a : argv) {
      if (!command.empty()) command += ' ';
      command += ShellQuote(a);
    }
    throw DeviceError("could not submit to Slurm: `" + command + "` " +
                      (r.status < 0 ? "did not run" : "exited with " + std::to_string(r.status)) +
                      (out.empty() ? std::string() : ": " + out) +
                      ". Check that the Slurm client commands are on PATH and SLURM_CONF names "
                      "the cluster's slurm.conf, then run the same command again (items already "
                      "done are kept)");
  }
  // The last line is the id (sbatch may print warnings before it).
  const size_t line = out.find_last_of('\n');
  if (line != std::string::npos) out = out.substr(line + 1);
  out = out.substr(0, out.find(';'));
  if (out.empty() || !std::all_of(out.begin(), out.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    throw DeviceError("sbatch did not print a job id (got '" + Trim(r.output) + "')");
  }
  return out;
}

std::string ArrayList(const std::vector<int>& shards) {
  std::string list;
  for (int s : shards) {
    if (!list.empty()) list += ',';
    list += std::to_string(s);
  }
  return list;
}

}  // namespace

std::string ShellQuote(const std::string& word) {
  if (!word.empty() && std::all_of(word.begin(), word.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || std::strchr("@%+=:,./_-", c);
      })) {
    return word;
  }
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

SlurmSite SlurmSite::Load(const std::string& yaml_path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path);
  } catch (const YAML::Exception& e) {
    throw InputError("cannot read the Slurm site file " + yaml_path + ": " + e.what() +
                     " (docs/cluster.md shows its keys)");
  }
  SlurmSite site;
  if (!root || root.IsNull()) return site;
  if (!root.IsMap()) throw InputError(yaml_path + ": expected key: value lines (docs/cluster.md)");
  const std::set<std::string> known = {"partition", "account", "setup", "zbrdf", "sbatch",
                                       "cpus_per_task", "memory", "time_limit_minutes"};
  for (const auto& kv : root) {
    const std::string key = kv.first.as<std::string>();
    if (!known.count(key)) {
      throw InputError(yaml_path + ": unknown key '" + key +
                       "'; the keys are partition, account, setup, zbrdf, sbatch, cpus_per_task, "
                       "memory, time_limit_minutes");
    }
  }
  try {
    if (root["partition"]) site.partition = root["partition"].as<std::string>();
    if (root["account"]) site.account = root["account"].as<std::string>();
    if (root["setup"]) site.setup = root["setup"].as<std::string>();
    if (root["zbrdf"]) site.zbrdf = root["zbrdf"].as<std::string>();
    if (root["memory"]) site.memory = root["memory"].as<std::string>();
    if (root["cpus_per_task"]) site.cpus_per_task = root["cpus_per_task"].as<int>();
    if (root["time_limit_minutes"]) site.time_limit_minutes = root["time_limit_minutes"].as<int>();
    if (root["sbatch"]) {
      const YAML::Node lines = root["sbatch"];
      if (lines.IsSequence()) {
        for (const auto& l : lines) site.sbatch_lines.push_back(l.as<std::string>());
      } else {
        site.sbatch_lines.push_back(lines.as<std::string>());
      }
    }
  } catch (const YAML::Exception& e) {
    throw InputError(yaml_path + ": " + e.what() + " (docs/cluster.md shows each key's type)");
  }
  if (site.cpus_per_task < 1 || site.cpus_per_task > 256) {
    throw InputError(yaml_path + ": cpus_per_task must be 1 to 256");
  }
  if (site.time_limit_minutes < 0) throw InputError(yaml_path + ": time_limit_minutes must be >= 0");
  return site;
}

nlohmann::json SlurmSite::ToJson() const {
  return {{"partition", partition}, {"account", account},         {"setup", setup},
          {"zbrdf", zbrdf},         {"sbatch", sbatch_lines},      {"cpus_per_task", cpus_per_task},
          {"memory", memory},       {"time_limit_minutes", time_limit_minutes}};
}

SlurmSite SlurmSite::FromJson(const nlohmann::json& j) {
  SlurmSite site;
  site.partition = j.value("partition", std::string());
  site.account = j.value("account", std::string());
  site.setup = j.value("setup", std::string());
  site.zbrdf = j.value("zbrdf", std::string());
  site.sbatch_lines = j.value("sbatch", std::vector<std::string>());
  site.cpus_per_task = j.value("cpus_per_task", 2);
  site.memory = j.value("memory", std::string("4G"));
  site.time_limit_minutes = j.value("time_limit_minutes", 0);
  return site;
}

int SlurmTimeLimitMinutes(double item_seconds, int items_per_shard) {
  const double minutes = 3.0 * std::max(1.0, item_seconds) * std::max(1, items_per_shard) / 60.0 + 5.0;
  return static_cast<int>(std::ceil(std::min(minutes, 7.0 * 24 * 60)));
}

SlurmSubmission SubmitSlurmBatch(const std::string& dir, const BatchManifest& manifest,
                                 int shard_count, const std::vector<int>& shards,
                                 const SlurmSite& site, double item_seconds) {
  if (shard_count < 1) throw InputError("--shards must be at least 1");
  const fs::path abs_dir = fs::absolute(dir).lexically_normal();
  const fs::path slurm_dir = abs_dir / "slurm";
  fs::create_directories(slurm_dir);
  SlurmSubmission sub;
  sub.shard_count = shard_count;
  sub.shards = shards;
  if (sub.shards.empty()) {
    for (int i = 0; i < shard_count; ++i) sub.shards.push_back(i);
  }
  const int items_per_shard =
      static_cast<int>((manifest.items.size() + static_cast<size_t>(shard_count) - 1) / shard_count);
  sub.time_limit_minutes = site.time_limit_minutes > 0
                               ? site.time_limit_minutes
                               : SlurmTimeLimitMinutes(item_seconds, items_per_shard);
  // Default: this binary (or, where that cannot be read, the zbrdf on the jobs' PATH).
  const std::string self = ExecutablePath();
  const std::string zbrdf = !site.zbrdf.empty() ? site.zbrdf : self.empty() ? "zbrdf" : self;
  const std::string cwd = fs::current_path().string();

  auto header = [&](const std::string& name, const std::string& output, int cpus,
                    const std::string& memory, int minutes) {
    std::ostringstream s;
    s << "#!/bin/bash\n"
      << "# Written by zbrdf (tools/slurm.h, docs/cluster.md) for the batch in " << abs_dir.string()
      << "\n#SBATCH --job-name=" << name << "\n#SBATCH --chdir=" << cwd
      << "\n#SBATCH --output=" << output << "\n#SBATCH --cpus-per-task=" << cpus
      << "\n#SBATCH --mem=" << memory << "\n#SBATCH --time=" << minutes << "\n";
    if (!site.partition.empty()) s << "#SBATCH --partition=" << site.partition << "\n";
    if (!site.account.empty()) s << "#SBATCH --account=" << site.account << "\n";
    for (const std::string& line : site.sbatch_lines) s << "#SBATCH " << line << "\n";
    s << "set -euo pipefail\n";
    if (!site.setup.empty()) s << site.setup << "\n";
    return s.str();
  };
  // The shards: the manifest's command line plus --shard; the workers use the task's CPUs.
  std::ostringstream shards_sh;
  shards_sh << header("zbrdf-" + manifest.command, (slurm_dir / "shard-%a.out").string(),
                      site.cpus_per_task, site.memory, sub.time_limit_minutes)
            << "export ZBRDF_THREADS=${SLURM_CPUS_PER_TASK:-" << site.cpus_per_task << "}\n"
            << "exec " << ShellQuote(zbrdf) << " " << ShellQuote(manifest.command);
  for (const std::string& a : manifest.args) shards_sh << " " << ShellQuote(a);
  shards_sh << " --shard \"${SLURM_ARRAY_TASK_ID}/" << shard_count << "\"\n";
  std::ostringstream merge_sh;
  merge_sh << header("zbrdf-merge", (slurm_dir / "merge-%j.out").string(), 1, "2G", 30)
           << "exec " << ShellQuote(zbrdf) << " batch merge " << ShellQuote(abs_dir.string()) << "\n";
  const std::string shards_path = (slurm_dir / "shards.sh").string();
  const std::string merge_path = (slurm_dir / "merge.sh").string();
  WriteFileAtomically(shards_path, shards_sh.str());
  WriteFileAtomically(merge_path, merge_sh.str());

  sub.array_job = SubmitScript({"--array=" + ArrayList(sub.shards), shards_path});
  sub.merge_job = SubmitScript({"--dependency=afterok:" + sub.array_job, "--kill-on-invalid-dep=yes",
                                merge_path});
  std::vector<nlohmann::json> all = SlurmSubmissions(dir);
  all.push_back({{"array_job", sub.array_job},
                 {"merge_job", sub.merge_job},
                 {"shard_count", shard_count},
                 {"shards", sub.shards},
                 {"time_limit_minutes", sub.time_limit_minutes},
                 {"item_seconds", item_seconds},
                 {"site", site.ToJson()},
                 {"submitted_unix_s", std::chrono::duration<double>(
                                          std::chrono::system_clock::now().time_since_epoch()).count()}});
  WriteFileAtomically((slurm_dir / "submissions.json").string(), nlohmann::json(all).dump(2) + "\n");
  return sub;
}

std::vector<nlohmann::json> SlurmSubmissions(const std::string& dir) {
  const nlohmann::json j = ReadJsonOrNull(dir + "/slurm/submissions.json");
  if (!j.is_array()) return {};
  return j.get<std::vector<nlohmann::json>>();
}

std::vector<std::string> LiveSlurmJobs(const std::string& dir) {
  std::vector<std::string> jobs;
  for (const nlohmann::json& s : SlurmSubmissions(dir)) {
    for (const char* key : {"array_job", "merge_job"}) {
      if (s.contains(key) && s[key].is_string()) jobs.push_back(s[key].get<std::string>());
    }
  }
  if (jobs.empty()) return {};
  std::string list;
  for (const std::string& j : jobs) {
    if (!list.empty()) list += ',';
    list += j;
  }
  // %i: "123_4" for an array task ("123_[5-7]" for pending ones), %A the array's job id.
  const SlurmCommandResult r = RunProcess({"squeue", "-h", "-r", "-j", list, "-o", "%i %A"});
  std::vector<std::string> live;
  if (r.status != 0) return live;
  std::istringstream lines(r.output);
  std::string id, array;
  while (lines >> id >> array) {
    live.push_back(id);
    live.push_back(array);
  }
  return live;
}

}  // namespace zbrdf
