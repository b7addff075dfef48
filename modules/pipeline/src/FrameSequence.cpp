#include "FrameSequence.h"

#include <algorithm>
#include <utility>

#include "ProcessUsage.h"

namespace avm::pipeline::detail
{
namespace fs = std::filesystem;

FrameSequence::FrameSequence(const fs::path& rawlog, unsigned repeat, unsigned readAhead, std::size_t firstIndex)
	: m_rawlog(rawlog), m_repeat(repeat), m_indexOffset(firstIndex), m_readAhead(readAhead)
{
	// Opened here, so a missing rawlog is an error of the constructor.
	m_reader = std::make_unique<io::RawlogFrameReader>(rawlog);
	m_reader->logging_enable_keep_record = true;
	if (m_readAhead > 0) m_thread = std::thread([this] { readAheadLoop(); });
}

FrameSequence::~FrameSequence() { close(); }

void FrameSequence::close()
{
	{
		std::lock_guard lock(m_mutex);
		m_stopRequested = true;
	}
	m_changed.notify_all();
	if (m_thread.joinable()) m_thread.join();
	absorbReader();
}

std::optional<io::RgbdFrame> FrameSequence::next()
{
	if (m_readAhead == 0) return m_stopRequested ? std::nullopt : read();

	std::unique_lock lock(m_mutex);
	m_changed.wait(lock, [this] { return !m_queue.empty() || m_readerDone; });
	if (m_queue.empty())
	{
		if (m_readerError) std::rethrow_exception(std::exchange(m_readerError, nullptr));
		return {};
	}
	std::optional<io::RgbdFrame> frame;
	frame.swap(m_queue.front());
	m_queue.pop_front();
	lock.unlock();
	m_changed.notify_all();
	return frame;
}

void FrameSequence::readAheadLoop()
{
	try
	{
		for (;;)
		{
			{
				std::unique_lock lock(m_mutex);
				m_changed.wait(lock, [this] { return m_queue.size() < m_readAhead || m_stopRequested; });
				if (m_stopRequested) break;
			}
			auto frame = read();
			if (!frame) break;
			{
				std::lock_guard lock(m_mutex);
				m_queue.push_back(std::move(frame));
			}
			m_changed.notify_all();
		}
	}
	catch (...)
	{
		std::lock_guard lock(m_mutex);
		m_readerError = std::current_exception();
	}
	{
		std::lock_guard lock(m_mutex);
		m_readerDone = true;
	}
	m_changed.notify_all();
}

std::optional<io::RgbdFrame> FrameSequence::read()
{
	for (;;)
	{
		auto frame = m_reader->next();
		if (frame)
		{
			m_lastTime = frame->timestamp();
			if (!m_firstTime) m_firstTime = m_lastTime;
			m_framesInReplay = frame->index + 1;
			frame->index += m_indexOffset;
			if (m_timeOffset != 0) frame->observation->timestamp = mrpt::Clock::fromDouble(m_lastTime + m_timeOffset);
			m_progress = (m_replay + m_reader->progress()) / m_repeat;
			return frame;
		}
		finishReplay();
		if (++m_replay >= m_repeat || m_framesInReplay == 0)
		{
			m_progress = 1.0;
			return {};
		}
		m_indexOffset += m_framesInReplay;
		// The next replay starts one frame period after this one ended.
		const double period = (m_lastTime - *m_firstTime) / std::max<std::size_t>(1, m_framesInReplay - 1);
		m_timeOffset += m_lastTime - *m_firstTime + period;
		m_reader = std::make_unique<io::RawlogFrameReader>(m_rawlog);
		m_reader->logging_enable_keep_record = true;
		m_readerAbsorbed = false;
	}
}

void FrameSequence::finishReplay()
{
	absorbReader();
	m_peaks.push_back(peakMemoryMb());
}

void FrameSequence::absorbReader()
{
	if (m_readerAbsorbed) return;
	m_skipped.insert(m_skipped.end(), m_reader->skipped().begin(), m_reader->skipped().end());
	m_log += m_reader->getLogAsString();
	m_readerAbsorbed = true;
}
}  // namespace avm::pipeline::detail
