#include "HelperProcess.h"

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#include <dlfcn.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

namespace beltrami
{

namespace
{

/// The input as a file descriptor positioned at its start.
int InputFile(const std::vector<char>& input)
{
  if (input.empty())
  {
    return open("/dev/null", O_RDONLY | O_CLOEXEC);
  }
  const int fd = memfd_create("beltrami-helper-input", MFD_CLOEXEC);
  if (fd < 0)
  {
    return -1;
  }
  std::size_t written = 0;
  while (written < input.size())
  {
    const ssize_t n = write(fd, input.data() + written, input.size() - written);
    if (n <= 0)
    {
      close(fd);
      return -1;
    }
    written += static_cast<std::size_t>(n);
  }
  lseek(fd, 0, SEEK_SET);
  return fd;
}

} // namespace

HelperProcessResult RunHelperProcess(const std::string& program, const std::vector<std::string>& arguments,
  const std::vector<char>& input, double maximumBytes, double timeout, const std::function<bool()>& keepGoing)
{
  const int in = InputFile(input);
  if (in < 0)
  {
    throw std::runtime_error("cannot hand the input to the helper '" + program + "'");
  }
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0)
  {
    close(in);
    throw std::runtime_error("cannot create a pipe for the helper '" + program + "'");
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in, 0);
  posix_spawn_file_actions_adddup2(&actions, fds[1], 1);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  std::vector<char*> argv = { const_cast<char*>(program.c_str()) };
  for (const std::string& a : arguments)
  {
    argv.push_back(const_cast<char*>(a.c_str()));
  }
  argv.push_back(nullptr);
  // The helper's heap on transparent huge pages (glibc >= 2.35): a fresh
  // process faults in all its memory, one 4 KiB page at a time otherwise,
  // which on virtual machines costs more than the work (TetGen on a 75k-
  // triangle surface: +20%).
  std::vector<std::string> environment;
  for (char** e = environ; e && *e; ++e)
  {
    if (std::strncmp(*e, "GLIBC_TUNABLES=", 15) != 0)
    {
      environment.emplace_back(*e);
    }
  }
  environment.emplace_back("GLIBC_TUNABLES=glibc.malloc.hugetlb=1");
  std::vector<char*> envp;
  for (std::string& e : environment)
  {
    envp.push_back(e.data());
  }
  envp.push_back(nullptr);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, program.c_str(), &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  close(fds[1]);
  close(in);
  if (spawned != 0)
  {
    close(fds[0]);
    throw std::runtime_error("cannot run the helper '" + program + "': " + std::strerror(spawned));
  }
  HelperProcessResult result;
  std::vector<char> buffer(1 << 16);
  const auto start = std::chrono::steady_clock::now();
  for (;;)
  {
    pollfd p{ fds[0], POLLIN, 0 };
    if (poll(&p, 1, 200) > 0)
    {
      const ssize_t n = read(fds[0], buffer.data(), buffer.size());
      if (n <= 0)
      {
        break; // end of its output: it has exited or is exiting
      }
      if (static_cast<double>(result.Output.size()) + static_cast<double>(n) > maximumBytes)
      {
        result.Overflow = true;
        break;
      }
      result.Output.insert(result.Output.end(), buffer.data(), buffer.data() + n);
    }
    if (timeout > 0.0 &&
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > timeout)
    {
      result.TimedOut = true;
      break;
    }
    if (keepGoing && !keepGoing())
    {
      result.Cancelled = true;
      break;
    }
  }
  close(fds[0]);
  if (result.Overflow || result.TimedOut || result.Cancelled)
  {
    kill(pid, SIGKILL);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
  {
  }
  if (WIFSIGNALED(status))
  {
    result.Signal = WTERMSIG(status);
  }
  else if (WIFEXITED(status))
  {
    result.ExitCode = WEXITSTATUS(status);
  }
  return result;
}

std::string HelperPathNextTo(const void* symbol, const std::string& name, const char* overrideVariable)
{
  if (const char* env = overrideVariable ? std::getenv(overrideVariable) : nullptr)
  {
    return env;
  }
  Dl_info info;
  if (dladdr(symbol, &info) && info.dli_fname)
  {
    const std::string library = info.dli_fname;
    const std::size_t slash = library.rfind('/');
    if (slash != std::string::npos)
    {
      return library.substr(0, slash + 1) + name;
    }
  }
  return name;
}

std::string ByteReader::String()
{
  const std::uint32_t n = this->Get<std::uint32_t>();
  if (n > this->Left())
  {
    throw std::runtime_error("malformed answer of the " + this->What);
  }
  std::string s(this->Bytes.data() + this->Position, n);
  this->Position += n;
  return s;
}

void ByteReader::Take(void* out, std::size_t n)
{
  if (n > this->Left())
  {
    throw std::runtime_error("malformed answer of the " + this->What);
  }
  std::memcpy(out, this->Bytes.data() + this->Position, n);
  this->Position += n;
}

} // namespace beltrami
