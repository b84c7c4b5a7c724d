"""asperity.statmodel"""
