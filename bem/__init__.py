"""asperity.bem"""
