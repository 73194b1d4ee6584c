"""markov"""
