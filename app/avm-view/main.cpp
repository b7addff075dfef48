// avm-view: a finished avm-map run (both .bt, trajectory, persons with their
// last shapes, regions) in the live view of avm-map --gui.
#include <mrpt/3rdparty/tclap/CmdLine.h>

#include <iostream>

#include "avm/io/ProgramMain.h"
#include "avm/viewer/MapView.h"

int main(int argc, char** argv)
{
	const int status = avm::io::runProgram("avm-view",
		"Shows a finished avm-map run (map_low.bt, map_high.bt, trajectory.txt, persons.csv, person_shapes.ply, "
		"stats.json) in a 3D window.",
		[&](avm::io::CommandLine& cmd)
		{
			TCLAP::UnlabeledValueArg<std::string> argDir("OUTDIR", "avm-map output folder", true, "", "OUTDIR", cmd);
			TCLAP::ValueArg<std::string> argShot("", "screenshot",
				"save what the X server shows of the window as a PNG after the first draw, then exit", false, "",
				"FILE.png", cmd);
			TCLAP::ValueArg<double> argSettle("", "settle",
				"[s] wait before the screenshot, for the GL thread to paint (default 2)", false, 2.0, "S", cmd);
			TCLAP::ValueArg<unsigned> argWidth("", "width", "[px] window width (default 1024)", false, 1024, "PX", cmd);
			TCLAP::ValueArg<unsigned> argHeight(
				"", "height", "[px] window height (default 768)", false, 768, "PX", cmd);
			cmd.parse(argc, argv);

			// Free space is in the snapshot from the start: the 'f' key shows it.
			auto snapshot = avm::viewer::snapshotOfRun(argDir.getValue(), {/*freeSpace*/ true});
			avm::viewer::TViewerOptions opt;
			opt.width = argWidth.getValue();
			opt.height = argHeight.getValue();
			opt.title = "avm-view " + argDir.getValue();
			avm::viewer::MapView view(opt);
			view.show(std::move(snapshot));
			if (!view.waitUntilDrawn(30)) throw std::runtime_error("the view did not draw within 30 s");
			if (argShot.isSet())
			{
				view.saveScreenshot(argShot.getValue(), argSettle.getValue());
				std::cout << "screenshot: " << argShot.getValue() << "\n";
				return 0;
			}
			std::cout << "close the window to quit\n";
			view.waitUntilClosed();
			return 0;
		});
	avm::viewer::exitAfterView(status);
}
