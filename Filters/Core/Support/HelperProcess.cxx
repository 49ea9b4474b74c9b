#include "Support/HelperProcess.h"

#include <algorithm>
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
#include <sys/socket.h>
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

/// Starts program with arguments, `in` as its standard input and `out` as
/// its standard output (closed in the child after dup2), standard error on
/// /dev/null, the heap on transparent huge pages (glibc >= 2.35: a fresh
/// process faults in all its memory, one 4 KiB page at a time otherwise,
/// which on machines where page faults are slow costs more than the work).  Returns the pid or
/// throws.
pid_t Spawn(const std::string& program, const std::vector<std::string>& arguments, int in, int out)
{
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in, 0);
  posix_spawn_file_actions_adddup2(&actions, out, 1);
  posix_spawn_file_actions_addopen(&actions, 2, "/dev/null", O_WRONLY, 0);
  std::vector<char*> argv = { const_cast<char*>(program.c_str()) };
  for (const std::string& a : arguments)
  {
    argv.push_back(const_cast<char*>(a.c_str()));
  }
  argv.push_back(nullptr);
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
  if (spawned != 0)
  {
    throw std::runtime_error("cannot run the helper '" + program + "': " + std::strerror(spawned));
  }
  return pid;
}

/// The timeout and cancel checks of the loops that read a helper's answer:
/// true (the reason recorded) when the helper must be stopped.
bool MustStop(std::chrono::steady_clock::time_point start, double timeout, const std::function<bool()>& keepGoing,
  HelperProcessResult& result)
{
  result.TimedOut =
    timeout > 0.0 && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > timeout;
  result.Cancelled = !result.TimedOut && keepGoing && !keepGoing();
  return result.TimedOut || result.Cancelled;
}

/// Waits for pid and records how it ended.
void Reap(pid_t pid, HelperProcessResult& result)
{
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
  pid_t pid = 0;
  try
  {
    pid = Spawn(program, arguments, in, fds[1]);
  }
  catch (...)
  {
    close(in);
    close(fds[0]);
    close(fds[1]);
    throw;
  }
  close(fds[1]);
  close(in);
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
    if (MustStop(start, timeout, keepGoing, result))
    {
      break;
    }
  }
  close(fds[0]);
  if (result.Overflow || result.TimedOut || result.Cancelled)
  {
    kill(pid, SIGKILL);
  }
  Reap(pid, result);
  return result;
}

PersistentHelperProcess::PersistentHelperProcess(std::string program, std::vector<std::string> arguments)
  : Program(std::move(program))
  , Arguments(std::move(arguments))
{
}

PersistentHelperProcess::~PersistentHelperProcess()
{
  HelperProcessResult ignored;
  Stop(ignored, false);
}

void PersistentHelperProcess::Stop(HelperProcessResult& result, bool killIt)
{
  if (Socket >= 0)
  {
    close(Socket); // the helper reads the end of its input and exits
    Socket = -1;
  }
  if (Pid > 0)
  {
    if (killIt)
    {
      kill(Pid, SIGKILL);
    }
    Reap(Pid, result);
    Pid = -1;
  }
}

HelperProcessResult PersistentHelperProcess::Request(const std::vector<char>& request, double maximumBytes,
  double timeout, const std::function<bool()>& keepGoing)
{
  std::lock_guard<std::mutex> lock(Mutex);
  HelperProcessResult result;
  if (Pid <= 0)
  {
    int sv[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0)
    {
      throw std::runtime_error("cannot create a socket for the helper '" + Program + "'");
    }
    try
    {
      Pid = Spawn(Program, Arguments, sv[1], sv[1]);
    }
    catch (...)
    {
      close(sv[0]);
      close(sv[1]);
      throw;
    }
    close(sv[1]);
    Socket = sv[0];
  }
  // The request (a helper that died makes send fail: MSG_NOSIGNAL, no SIGPIPE).
  const std::uint64_t length = request.size();
  const auto sendAll = [this](const char* data, std::size_t n) {
    while (n > 0)
    {
      const ssize_t w = send(Socket, data, n, MSG_NOSIGNAL);
      if (w < 0 && errno == EINTR)
      {
        continue;
      }
      if (w <= 0)
      {
        return false;
      }
      data += w;
      n -= static_cast<std::size_t>(w);
    }
    return true;
  };
  if (!sendAll(reinterpret_cast<const char*>(&length), sizeof(length)) ||
    !sendAll(request.data(), request.size()))
  {
    Stop(result, true);
    if (!result.Signal)
    {
      result.Signal = SIGPIPE; // it died before reading the request
    }
    return result;
  }
  // The answer: a length, then that many bytes.
  std::vector<char> header;
  std::uint64_t expected = 0;
  bool haveLength = false;
  std::vector<char> buffer(1 << 16);
  const auto start = std::chrono::steady_clock::now();
  for (;;)
  {
    if (haveLength && result.Output.size() == expected)
    {
      result.ExitCode = 0;
      return result; // the helper keeps running
    }
    pollfd p{ Socket, POLLIN, 0 };
    if (poll(&p, 1, 200) > 0)
    {
      const std::size_t want = haveLength ? std::min<std::size_t>(buffer.size(), expected - result.Output.size())
                                          : sizeof(expected) - header.size();
      const ssize_t n = recv(Socket, buffer.data(), want, 0);
      if (n < 0 && errno == EINTR)
      {
        continue;
      }
      if (n <= 0)
      {
        Stop(result, false); // it died while working: a crash
        if (!result.Signal && result.ExitCode == 0)
        {
          result.ExitCode = -1; // it ended without answering
        }
        return result;
      }
      if (!haveLength)
      {
        header.insert(header.end(), buffer.data(), buffer.data() + n);
        if (header.size() == sizeof(expected))
        {
          std::memcpy(&expected, header.data(), sizeof(expected));
          haveLength = true;
          if (static_cast<double>(expected) > maximumBytes)
          {
            result.Overflow = true;
            break;
          }
          result.Output.reserve(static_cast<std::size_t>(expected));
        }
      }
      else
      {
        result.Output.insert(result.Output.end(), buffer.data(), buffer.data() + n);
      }
    }
    if (MustStop(start, timeout, keepGoing, result))
    {
      break;
    }
  }
  Stop(result, true);
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
