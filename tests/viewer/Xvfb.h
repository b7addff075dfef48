// A private X server for one test binary (Xvfb, installed by
// scripts/install-deps.sh): started on a free display, DISPLAY pointed at it,
// ended with the test process. The suite needs no display of its own.
#pragma once

#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <stdexcept>
#include <string>

namespace avm::test
{
class XvfbServer
{
   public:
	explicit XvfbServer(const std::string& screen = "1700x800x24")
	{
		int fds[2];
		if (::pipe(fds) != 0) throw std::runtime_error("pipe failed");
		m_pid = ::fork();
		if (m_pid == 0)
		{
			::close(fds[0]);
			::prctl(PR_SET_PDEATHSIG, SIGTERM);  // the server ends with the test process
			const std::string fd = std::to_string(fds[1]);
			::execlp("Xvfb", "Xvfb", "-displayfd", fd.c_str(), "-screen", "0", screen.c_str(), "-nolisten", "tcp",
				static_cast<char*>(nullptr));
			::_exit(127);
		}
		::close(fds[1]);
		std::string display;
		char c;
		while (::read(fds[0], &c, 1) == 1 && c != '\n') display += c;
		::close(fds[0]);
		if (m_pid < 0 || display.empty())
			throw std::runtime_error("Xvfb did not start (install xvfb: scripts/install-deps.sh)");
		m_display = ":" + display;
		// wx and Xlib keep the display open until the process ends: the server
		// must outlive them, so the destructor leaves it to PR_SET_PDEATHSIG.
		::setenv("DISPLAY", m_display.c_str(), 1);
	}
	const std::string& display() const { return m_display; }

   private:
	pid_t m_pid = -1;
	std::string m_display;
};
}  // namespace avm::test
