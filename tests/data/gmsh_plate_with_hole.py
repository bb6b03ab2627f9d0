"""A plate with a hole, meshed by Gmsh (the `gmsh` Python package) for tests/gmsh_read.rs.

usage: python3 gmsh_plate_with_hole.py OUT.msh ORDER BINARY
The plate [-w/2, w/2] x [-L, 0] hangs from its top edge (physical curve "rotation", centred on
the origin); a hole of radius r is centred at (0, -c). Dimensions must match the test.
"""
import sys, gmsh
out, order, binary = sys.argv[1], int(sys.argv[2]), sys.argv[3] == "1"
w, L, c, r, h = 0.04, 0.25, 0.18, 0.012, 0.006
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("plate")
occ = gmsh.model.occ
plate = occ.addRectangle(-w / 2, -L, 0, w, L)
hole = occ.addDisk(0, -c, 0, r, r)
occ.cut([(2, plate)], [(2, hole)])
occ.synchronize()
top = [t for (d, t) in gmsh.model.getEntities(1)
       if abs(gmsh.model.occ.getCenterOfMass(1, t)[1]) < 1e-12]
assert len(top) == 1, top
gmsh.model.addPhysicalGroup(1, top, name="rotation")
gmsh.model.addPhysicalGroup(2, [t for (d, t) in gmsh.model.getEntities(2)], name="plate")
gmsh.option.setNumber("Mesh.MeshSizeMax", h)
gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
gmsh.option.setNumber("Mesh.Binary", 1 if binary else 0)
gmsh.model.mesh.generate(2)
gmsh.model.mesh.setOrder(order)
gmsh.write(out)
gmsh.finalize()
