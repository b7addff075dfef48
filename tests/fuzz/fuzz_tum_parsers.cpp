// Any text as rgb.txt / associations.txt / groundtruth.txt / a 4x4 transform:
// parsed or rejected with std::runtime_error, never a crash.
#include <stdexcept>

#include "FuzzInput.h"
#include "avm/io/Trajectory.h"
#include "avm/io/TumDataset.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
	const avm::fuzz::InputFile file(data, size, ".txt");
	const auto attempt = [](auto&& parse)
	{
		try
		{
			parse();
		}
		catch (const std::runtime_error&)
		{
		}
	};
	attempt(
		[&]
		{
			const auto list = avm::io::readTumFileList(file.path());
			avm::io::associateNearest(list, list, 0.02);
		});
	attempt([&] { avm::io::readAssociations(file.path()); });
	attempt(
		[&]
		{
			const auto t = avm::io::readTumTrajectory(file.path());
			if (!t.empty()) avm::io::interpolatePose(t, 0.5 * (t.front().timestamp + t.back().timestamp));
		});
	attempt([&] { avm::io::readRigidTransformFile(file.path()); });
	return 0;
}
