from paraview.simple import *

camera = PNGSeriesReader(FileNames=["Testing/Data/camera.png"])
denoised = ImageBeltramiDenoising(Input=camera)
denoised.ArrayToSmooth = ["POINTS", "PNGImage"]
denoised.UpdatePipeline()
print(denoised.PointData.keys())
