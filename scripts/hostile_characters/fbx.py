import sys
def fbx(path, corners=3, cluster_indexes=None):
    n = corners
    import math
    verts = []
    for k in range(n):
        a = 2 * math.pi * k / n
        verts += ["%.5g" % math.cos(a), "%.5g" % (1 + math.sin(a)), "0"]
    poly = [str(k) for k in range(n - 1)] + [str(-(n - 1) - 1)]
    ci = cluster_indexes if cluster_indexes is not None else [0]
    out = """; FBX 7.4.0 project file
FBXHeaderExtension:  {
	FBXHeaderVersion: 1003
	FBXVersion: 7400
}
GlobalSettings:  {
	Version: 1000
}
Objects:  {
	Geometry: 1000, "Geometry::body", "Mesh" {
		Vertices: *%d {
			a: %s
		}
		PolygonVertexIndex: *%d {
			a: %s
		}
		GeometryVersion: 124
	}
	Model: 2000, "Model::body", "Mesh" {
		Version: 232
	}
	Model: 3000, "Model::Hips", "LimbNode" {
		Version: 232
	}
	Model: 3001, "Model::Spine", "LimbNode" {
		Version: 232
		Properties70:  {
			P: "Lcl Translation", "Lcl Translation", "", "A",0,1,0
		}
	}
	NodeAttribute: 6000, "NodeAttribute::Hips", "LimbNode" {
		TypeFlags: "Skeleton"
	}
	NodeAttribute: 6001, "NodeAttribute::Spine", "LimbNode" {
		TypeFlags: "Skeleton"
	}
	Deformer: 4000, "Deformer::skin", "Skin" {
		Version: 101
		Link_DeformAcuracy: 50
	}
	Deformer: 5000, "SubDeformer::c0", "Cluster" {
		Version: 100
		Indexes: *%d {
			a: %s
		}
		Weights: *%d {
			a: %s
		}
		Transform: *16 {
			a: 1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1
		}
		TransformLink: *16 {
			a: 1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1
		}
	}
}
Connections:  {
	C: "OO",2000,0
	C: "OO",3000,0
	C: "OO",3001,3000
	C: "OO",6000,3000
	C: "OO",6001,3001
	C: "OO",1000,2000
	C: "OO",4000,1000
	C: "OO",5000,4000
	C: "OO",3000,5000
}
""" % (len(verts), ",".join(verts), len(poly), ",".join(poly), len(ci), ",".join(map(str, ci)), len(ci), ",".join(["1"] * len(ci)))
    open(path, "w").write(out)
OUT, which = sys.argv[1], sys.argv[2]
if which == "tri":
    fbx(OUT + "/f3_polygon_%s.fbx" % sys.argv[3], corners=int(sys.argv[3]))
if which == "cl":
    fbx(OUT + "/f7_clusters.fbx", corners=3, cluster_indexes=[0, 1, 2, 7, -1])
if which == "degenerate":
    n = int(sys.argv[3])
    fbx(OUT + "/f3_degenerate_%d.fbx" % n, corners=3)
    s = open(OUT + "/f3_degenerate_%d.fbx" % n).read()
    poly = [str(k % 3) for k in range(n - 1)] + [str(-((n - 1) % 3) - 1)]
    s = s.replace("PolygonVertexIndex: *3 {\n\t\t\ta: 0,1,-3", "PolygonVertexIndex: *%d {\n\t\t\ta: %s" % (n, ",".join(poly)))
    open(OUT + "/f3_degenerate_%d.fbx" % n, "w").write(s)
