// Runs a fuzz target over every file in the folders given (seed corpus and
// regression inputs), so inputs that once crashed stay tested in every build.
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

int main(int argc, char** argv)
{
	std::size_t inputs = 0;
	for (int i = 1; i < argc; ++i)
	{
		if (!std::filesystem::is_directory(argv[i])) continue;
		for (const auto& e : std::filesystem::directory_iterator(argv[i]))
		{
			if (!e.is_regular_file()) continue;
			std::ifstream in(e.path(), std::ios::binary);
			const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), {});
			LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
			++inputs;
		}
	}
	std::printf("replayed %zu inputs\n", inputs);
	return inputs > 0 ? 0 : 1;
}
