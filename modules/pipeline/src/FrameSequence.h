// The frames avm-map maps: the rawlog read `repeat` times in a row as one
// sequence, optionally read ahead on a thread of its own. Reading a frame of a
// gzip rawlog with PNG colour (gunzip of the entry, PNG decoding) costs about
// 15 ms of CPU; a plain rawlog with the colour inside (the default dataset's
// form) little more than the copy.
#pragma once

#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "avm/io/RawlogFrameReader.h"
#include "avm/io/RgbdFrame.h"

namespace avm::pipeline::detail
{
class FrameSequence
{
   public:
	/** readAhead = 0 reads on the caller's thread; otherwise a reader thread
	 *  keeps up to readAhead frames decoded and waiting. The frames are
	 *  numbered from firstIndex (a continued session's, on from the earlier
	 *  sessions'). */
	FrameSequence(const std::filesystem::path& rawlog, unsigned repeat, unsigned readAhead, std::size_t firstIndex = 0);
	~FrameSequence();  //!< stops and joins the reader thread
	FrameSequence(const FrameSequence&) = delete;
	FrameSequence& operator=(const FrameSequence&) = delete;

	/** The next frame in order, or nothing at the end. Frame indices and
	 *  timestamps go on across replays. Rethrows the reader's error (corrupt
	 *  rawlog, missing images folder) once the frames before it are consumed. */
	std::optional<io::RgbdFrame> next();

	/** Stops reading (the reader thread is joined). The accessors below are
	 *  valid after close(). */
	void close();
	const std::vector<std::string>& skipped() const { return m_skipped; }
	const std::string& log() const { return m_log; }
	/** Peak memory [MiB] of the process at the end of each replay. */
	const std::vector<double>& peakMemoryPerReplay() const { return m_peaks; }

	/** Fraction of the whole sequence read so far, 0..1; any thread. */
	double progress() const { return m_progress.load(); }

   private:
	std::optional<io::RgbdFrame> read();
	void finishReplay();
	/** Takes over the current reader's skipped frames and log, once. */
	void absorbReader();
	void readAheadLoop();

	// Used by whichever thread reads.
	std::filesystem::path m_rawlog;
	unsigned m_repeat, m_replay = 0;
	std::unique_ptr<io::RawlogFrameReader> m_reader;
	bool m_readerAbsorbed = false;
	std::size_t m_indexOffset = 0, m_framesInReplay = 0;
	std::optional<double> m_firstTime;
	double m_lastTime = 0, m_timeOffset = 0;
	std::vector<std::string> m_skipped;
	std::string m_log;
	std::vector<double> m_peaks;
	std::atomic<double> m_progress{0};

	// Hand-over between the reader thread and the caller.
	unsigned m_readAhead;
	std::mutex m_mutex;
	std::condition_variable m_changed;
	std::deque<std::optional<io::RgbdFrame>> m_queue;  // never holds an empty optional
	bool m_readerDone = false, m_stopRequested = false;
	std::exception_ptr m_readerError;
	std::thread m_thread;
};
}  // namespace avm::pipeline::detail
