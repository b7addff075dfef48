#include "DetectApp.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <stdexcept>

#include "avm/io/AtomicFile.h"
#include "avm/io/RawlogFrameReader.h"
#include "avm/io/RgbdFrame.h"
#include "avm/io/TimingSummary.h"

namespace avm::apps::detect
{
namespace fs = std::filesystem;
using detection::Detection;

cv::Mat drawDetections(const cv::Mat& bgr, const std::vector<Detection>& detections)
{
	cv::Mat out = bgr.clone();
	for (const auto& d : detections)
	{
		const cv::Scalar colour = d.className == "person" ? cv::Scalar(0, 0, 255) : cv::Scalar(255, 128, 0);
		cv::rectangle(out, d.box, colour, 2);
		char label[96];
		std::snprintf(label, sizeof(label), "%s %.2f", d.className.c_str(), d.score);
		const cv::Point at(static_cast<int>(d.box.x), std::max(12, static_cast<int>(d.box.y) - 4));
		cv::putText(out, label, at, cv::FONT_HERSHEY_SIMPLEX, 0.5, colour, 1, cv::LINE_AA);
	}
	return out;
}

void writeImage(const fs::path& file, const cv::Mat& image)
{
	io::writeFileAtomically(file,
		[&](const fs::path& tmp)
		{
			bool ok = false;
			try
			{
				ok = cv::imwrite(tmp.string(), image);
			}
			catch (const cv::Exception& e)
			{
				throw std::runtime_error(file.string() + ": cannot write image (" + e.err + ")");
			}
			if (!ok) throw std::runtime_error(file.string() + ": cannot write image (unknown extension or folder?)");
		});
}

std::string summaryText(const detection::LabelRawlogSummary& s)
{
	std::string text =
		"frames:             " + std::to_string(s.frames) +
		"\ndetected frames:    " + std::to_string(s.detectedFrames) +
		"\nframes with person: " + std::to_string(s.framesWithPerson) +
		"\npersons:            " + std::to_string(s.persons) + "\nrawlog:             " + s.rawlog.string() +
		"\ndetections:         " + s.detectionsFile.string() +
		"\nimages:             " + (s.imagesDir.empty() ? std::string("embedded") : s.imagesDir.string()) +
		"\nnot labelled:       " + std::to_string(s.skipped.size()) + "\n";
	for (const auto& m : s.skipped) text += "  " + m + "\n";
	return text;
}

std::vector<cv::Mat> loadColourImages(const fs::path& rawlog, std::size_t maxFrames)
{
	io::RawlogFrameReader reader(rawlog);
	std::vector<cv::Mat> images;
	while (auto f = reader.next())
	{
		images.push_back(io::colourImage(*f->observation).clone());
		f->observation->unload();
		if (maxFrames && images.size() >= maxFrames) break;
	}
	if (images.empty()) throw std::runtime_error(rawlog.string() + ": no RGB-D frame with a colour image");
	return images;
}

DetectorBenchmark benchmarkDetector(detection::DetectorBase& detector, const std::vector<cv::Mat>& images, int threads)
{
	if (images.empty()) throw std::invalid_argument("benchmark needs at least one image");
	DetectorBenchmark b;
	b.threads = threads;
	io::TimingSamples ms;
	detector.detect(images.front());  // first call allocates the network's buffers
	for (const auto& img : images)
	{
		const auto t0 = std::chrono::steady_clock::now();
		const auto persons = detection::personsOnly(detector.detect(img));
		ms.add(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
		b.persons += persons.size();
		if (!persons.empty()) ++b.framesWithPerson;
	}
	b.times = ms.summary();
	return b;
}

std::string benchmarkTable(const std::vector<DetectorBenchmark>& rows)
{
	std::string s =
		"| threads | frames | frames with a person | persons | mean [ms] | median [ms] | p95 [ms] | max [ms] |\n"
		"|---:|---:|---:|---:|---:|---:|---:|---:|\n";
	for (const auto& b : rows)
	{
		char line[256];
		std::snprintf(line, sizeof(line), "| %d | %zu | %zu | %zu | %.1f | %.1f | %.1f | %.1f |\n", b.threads,
			b.times.count, b.framesWithPerson, b.persons, b.times.meanMs, b.times.medianMs, b.times.p95Ms,
			b.times.maxMs);
		s += line;
	}
	return s;
}
}  // namespace avm::apps::detect
