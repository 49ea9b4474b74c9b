from paraview.simple import *

wavelet = Wavelet(WholeExtent=[0, 63, 0, 63, 0, 0])
operators = BeltramiOperators(Input=wavelet)
operators.DataArray = ["POINTS", "RTData"]
operators.ContrastScale = 0.05
operators.UpdatePipeline()
print(operators.PointData["EdgeIndicator"].GetRange())
