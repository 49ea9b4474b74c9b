from paraview.simple import *

bunny = OpenDataFile("Testing/Data/bunny00.off")
smoothed = ImplicitFairing(Input=bunny)
smoothed.UpdatePipeline()
data = servermanager.Fetch(smoothed)
print("time step chosen:", data.GetFieldData().GetArray("FairingTimeStep").GetValue(0))
# A step by hand: 3 order-1 steps of 2 h^2.
smoothed.Order = "L"
smoothed.TimeStep = 2.0
smoothed.NumberOfIterations = 3
smoothed.UpdatePipeline()
