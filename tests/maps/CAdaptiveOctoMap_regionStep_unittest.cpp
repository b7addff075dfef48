// Persons enter the map once a frame: a program whose persons come through
// observePersons takes each depth image's region step itself
// (CAdaptiveOctoMap::prepareRegions, as avm-map does), and the insertion of
// that image then reads none of its person labels; a stock MRPT app, which
// gives its persons as the observation's labels, gets both from the insertion.
#include <gtest/gtest.h>

#include "BonnFrames.h"
#include "avm/plugin/CAdaptiveOctoMap.h"

using avm::CAdaptiveOctoMap;

TEST(CAdaptiveOctoMapRegionStep, APreparedImageIsInsertedWithoutReadingItsLabelsOnce)
{
	const auto f = avm::test::bonnFrames(1, 1).front();
	const auto labelled = avm::test::withPersonAtCentre(f);

	CAdaptiveOctoMap stockApp;
	ASSERT_TRUE(stockApp.insertObservation(*labelled, f.pose));
	EXPECT_EQ(stockApp.personTracks().size(), 1u) << "a stock app's labels are read by the insertion";
	EXPECT_EQ(stockApp.highResolutionRegions().size(), 1u);

	CAdaptiveOctoMap prepared;
	prepared.prepareRegions(*labelled, f.pose);
	ASSERT_TRUE(prepared.insertObservation(*labelled, f.pose));
	EXPECT_TRUE(prepared.personTracks().empty()) << "the labels of a prepared image were read";
	EXPECT_TRUE(prepared.highResolutionRegions().empty());

	// The step is taken for one insertion: the next one, unprepared, reads them.
	ASSERT_TRUE(prepared.insertObservation(*labelled, f.pose));
	EXPECT_EQ(prepared.personTracks().size(), 1u);
}
