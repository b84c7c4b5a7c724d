"""asperity.topo"""
